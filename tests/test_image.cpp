// host/image: display transform, file formats, comparison metrics. Expected
// values are worked out by hand, not by calling the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "host/error.h"
#include "host/image/image.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "host/image/tonemap.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

using test::slurp;

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

DisplaySettings settings(ToneMap tm, float exposure = 1.0f, float gamma = 1.0f) {
  DisplaySettings d;
  d.tonemap = tm;
  d.exposure_scale = exposure;
  d.gamma = gamma;
  return d;
}

// A 3x2 image whose pixels are all different, with values above 1, so
// orientation or channel-order mistakes and clamping show up.
ImageF sample_hdr() {
  ImageF img(3, 2);
  const float values[18] = {0.0f, 0.25f, 0.5f,  1.0f,   2.0f,  4.0f,  0.125f, 0.75f, 3.5f,
                            8.0f, 0.01f, 1e-6f, 100.0f, 0.33f, 0.66f, 0.9f,   0.1f,  12.25f};
  std::memcpy(img.rgb.data(), values, sizeof values);
  return img;
}

const auto error_message = test::error_of;

// ---- tone mapping -------------------------------------------------------

TEST(ToneMap, ParseAcceptsNamesCaseInsensitively) {
  EXPECT_EQ(parse_tonemap("linear"), ToneMap::Linear);
  EXPECT_EQ(parse_tonemap("Reinhard"), ToneMap::Reinhard);
  EXPECT_EQ(parse_tonemap("ACES"), ToneMap::Aces);
  for (ToneMap tm : {ToneMap::Linear, ToneMap::Reinhard, ToneMap::Aces})
    EXPECT_EQ(parse_tonemap(tonemap_name(tm)), tm);
}

TEST(ToneMap, ParseErrorListsValidNames) {
  const std::string msg = error_message([] { parse_tonemap("filmic"); });
  EXPECT_NE(msg.find("filmic"), std::string::npos) << msg;
  EXPECT_NE(msg.find("linear"), std::string::npos) << msg;
  EXPECT_NE(msg.find("reinhard"), std::string::npos) << msg;
  EXPECT_NE(msg.find("aces"), std::string::npos) << msg;
}

TEST(ToneMap, CurvesAtHandComputedPoints) {
  EXPECT_FLOAT_EQ(tonemap_curve(ToneMap::Linear, 0.3f), 0.3f);
  EXPECT_FLOAT_EQ(tonemap_curve(ToneMap::Reinhard, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(tonemap_curve(ToneMap::Reinhard, 3.0f), 0.75f);
  EXPECT_FLOAT_EQ(tonemap_curve(ToneMap::Aces, 0.0f), 0.0f);
  // (2.51 + 0.03) / (2.43 + 0.59 + 0.14) = 2.54 / 3.16
  EXPECT_NEAR(tonemap_curve(ToneMap::Aces, 1.0f), 2.54 / 3.16, 1e-6);
  // x = 0.5: 0.5 * 1.285 / (0.5 * 1.805 + 0.14) = 0.6425 / 1.0425
  EXPECT_NEAR(tonemap_curve(ToneMap::Aces, 0.5f), 0.6425 / 1.0425, 1e-6);
}

TEST(ToneMap, AcesIsMonotoneAndSaturates) {
  const DisplaySettings d = settings(ToneMap::Aces);
  float prev = -1.0f;
  for (int i = 0; i <= 2000; ++i) {
    const float x = i * 0.01f;
    const float y = display_value(x, d);
    EXPECT_GE(y, prev) << "at x = " << x;
    prev = y;
  }
  EXPECT_EQ(display_byte(0.0f, d), 0);
  EXPECT_EQ(display_byte(100.0f, d), 255);
}

TEST(ToneMap, LinearClampsAndRoundsToNearest) {
  const DisplaySettings d = settings(ToneMap::Linear);
  EXPECT_EQ(display_byte(-0.5f, d), 0);
  EXPECT_EQ(display_byte(0.0f, d), 0);
  EXPECT_EQ(display_byte(0.5f, d), 128);        // 127.5 + 0.5
  EXPECT_EQ(display_byte(1.0f / 255.0f, d), 1);
  EXPECT_EQ(display_byte(0.4f / 255.0f, d), 0);  // rounds down below half a step
  EXPECT_EQ(display_byte(0.6f / 255.0f, d), 1);  // and up above it
  EXPECT_EQ(display_byte(1.0f, d), 255);
  EXPECT_EQ(display_byte(7.0f, d), 255);
}

TEST(ToneMap, ExposureScalesBeforeTheCurve) {
  EXPECT_EQ(display_byte(0.25f, settings(ToneMap::Linear, 2.0f)), 128);
  // Reinhard of 0.5 * 2 = 1 is 0.5; applying exposure after the curve would give 2/3.
  EXPECT_EQ(display_byte(0.5f, settings(ToneMap::Reinhard, 2.0f)), 128);
  EXPECT_EQ(display_byte(0.5f, settings(ToneMap::Reinhard, 1.0f)), 85);  // 1/3 * 255 = 85.0
}

TEST(ToneMap, GammaEncodesAfterTheCurve) {
  // 0.5^(1/2.2) = 0.72974; * 255 + 0.5 = 186.58
  EXPECT_EQ(display_byte(0.5f, settings(ToneMap::Linear, 1.0f, 2.2f)), 186);
  // 0.25^(1/2) = 0.5
  EXPECT_EQ(display_byte(0.25f, settings(ToneMap::Linear, 1.0f, 2.0f)), 128);
  // Reinhard(1) = 0.5 then 0.5^(1/2) = 0.70711; * 255 + 0.5 = 180.81
  EXPECT_EQ(display_byte(1.0f, settings(ToneMap::Reinhard, 1.0f, 2.0f)), 180);
}

TEST(ToneMap, NonFiniteInputsMapToDefinedValues) {
  for (ToneMap tm : {ToneMap::Linear, ToneMap::Reinhard, ToneMap::Aces}) {
    for (float gamma : {1.0f, 2.2f}) {
      const DisplaySettings d = settings(tm, 1.0f, gamma);
      EXPECT_EQ(display_byte(kNaN, d), 0) << tonemap_name(tm);
      EXPECT_EQ(display_byte(kInf, d), 255) << tonemap_name(tm);
      EXPECT_EQ(display_byte(-kInf, d), 0) << tonemap_name(tm);
      EXPECT_EQ(display_byte(std::numeric_limits<float>::max(), d), 255) << tonemap_name(tm);
      EXPECT_EQ(display_byte(-std::numeric_limits<float>::max(), d), 0) << tonemap_name(tm);
    }
  }
  // Finite HDR value times a huge exposure overflows to +Inf: still white.
  EXPECT_EQ(display_byte(1e30f, settings(ToneMap::Aces, 1e30f)), 255);
}

TEST(ToneMap, ToDisplayConvertsEveryChannel) {
  ImageF hdr(2, 1);
  const float v[6] = {1.0f, 0.0f, kNaN, 3.0f, kInf, 0.5f};
  std::memcpy(hdr.rgb.data(), v, sizeof v);
  const Image8 out = to_display(hdr, settings(ToneMap::Reinhard));
  ASSERT_EQ(out.width, 2);
  ASSERT_EQ(out.height, 1);
  const std::vector<uint8_t> expect = {128, 0, 0, 191, 255, 85};  // 0.75*255+0.5 = 191.75
  EXPECT_EQ(out.rgb, expect);
}

TEST(ToneMap, InvalidSettingsAreRejected) {
  const ImageF hdr(1, 1, 0.5f);
  EXPECT_THROW(to_display(hdr, settings(ToneMap::Linear, 1.0f, 0.0f)), Error);
  EXPECT_THROW(to_display(hdr, settings(ToneMap::Linear, 1.0f, -2.0f)), Error);
  EXPECT_THROW(to_display(hdr, settings(ToneMap::Linear, kNaN, 1.0f)), Error);
  EXPECT_THROW(to_display(hdr, settings(ToneMap::Linear, -1.0f, 1.0f)), Error);
}

// ---- writers and readers ------------------------------------------------

TEST(ImageIO, PpmBytesAreExact) {
  ImageF hdr(2, 2);
  const float v[12] = {1, 0, 0, 0, 1, 0,            // top row: red, green
                       0, 0, 1, 0.5f, 0.5f, 0.5f};  // bottom row: blue, grey
  std::memcpy(hdr.rgb.data(), v, sizeof v);
  const std::string path = test::temp_dir() + "/exact.ppm";
  write_image(path, hdr, DisplaySettings{});
  EXPECT_EQ(slurp(path), "P3\n2 2\n255\n255 0 0\n0 255 0\n0 0 255\n128 128 128\n");
}

TEST(ImageIO, PpmRoundTripsThroughReader) {
  const ImageF hdr = sample_hdr();
  const DisplaySettings d = settings(ToneMap::Aces, 0.7f, 2.2f);
  const std::string path = test::temp_dir() + "/round.PPM";  // extension case must not matter
  write_image(path, hdr, d);
  const Image8 back = read_image8(path);
  const Image8 expect = to_display(hdr, d);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.rgb, expect.rgb);
}

TEST(ImageIO, ReadsAsciiPpmWithCommentsAndOtherMaxval) {
  const std::string path = test::temp_dir() + "/comment.ppm";
  spit(path, "P3\n# made by hand\n2 1 # size\n15\n15 0 7\n# mid\n1 2 3\n");
  const Image8 img = read_image8(path);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  // v * 255 / 15 rounded: 15 -> 255, 7 -> 119, 1 -> 17, 2 -> 34, 3 -> 51
  const std::vector<uint8_t> expect = {255, 0, 119, 17, 34, 51};
  EXPECT_EQ(img.rgb, expect);
}

TEST(ImageIO, MalformedAsciiPpmIsAnError) {
  const std::string path = test::temp_dir() + "/short.ppm";
  spit(path, "P3\n2 2\n255\n1 2 3\n");
  const std::string msg = error_message([&] { read_image8(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
}

TEST(ImageIO, PngRoundTripIsExactIn8Bits) {
  const ImageF hdr = sample_hdr();
  const DisplaySettings d = settings(ToneMap::Reinhard, 1.5f, 2.2f);
  const std::string path = test::temp_dir() + "/round.png";
  write_image(path, hdr, d);
  EXPECT_EQ(slurp(path).substr(1, 3), "PNG");
  const Image8 back = read_image8(path);
  const Image8 expect = to_display(hdr, d);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  EXPECT_EQ(back.rgb, expect.rgb);
}

TEST(ImageIO, PfmLayoutIsBottomRowFirstLittleEndian) {
  ImageF hdr(1, 2);
  const float v[6] = {1.0f, 2.0f, 3.0f,   // top row
                      4.0f, 5.0f, 6.0f};  // bottom row
  std::memcpy(hdr.rgb.data(), v, sizeof v);
  const std::string path = test::temp_dir() + "/layout.pfm";
  write_image(path, hdr, DisplaySettings{});
  const std::string bytes = slurp(path);
  const std::string header = "PF\n1 2\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 6 * 4);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  // 4.0f = 0x40800000, 1.0f = 0x3F800000: little-endian, bottom row first,
  // so the top row's 1.0f is the fourth float, i.e. in the last row stored.
  EXPECT_EQ(bytes.substr(header.size(), 4), std::string("\x00\x00\x80\x40", 4));
  EXPECT_EQ(bytes.substr(header.size() + 12, 4), std::string("\x00\x00\x80\x3f", 4));
}

TEST(ImageIO, PfmRoundTripIsExactAndScaledByExposureOnly) {
  const ImageF hdr = sample_hdr();
  const std::string path = test::temp_dir() + "/round.pfm";
  // Tone curve and gamma must not touch HDR output; exposure must.
  write_image(path, hdr, settings(ToneMap::Aces, 2.0f, 2.2f));
  const ImageF back = read_pfm(path);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  for (size_t i = 0; i < hdr.rgb.size(); ++i) EXPECT_EQ(back.rgb[i], hdr.rgb[i] * 2.0f) << "index " << i;
  EXPECT_EQ(read_hdr_image(path).rgb, back.rgb);
}

TEST(ImageIO, ReadsBigEndianAndGreyscalePfm) {
  const std::string path = test::temp_dir() + "/be.pfm";
  // 2x1 greyscale, positive scale = big-endian: 0.5f = 0x3F000000, 2.0f = 0x40000000.
  spit(path, std::string("Pf\n2 1\n1.0\n") + std::string("\x3f\x00\x00\x00\x40\x00\x00\x00", 8));
  const ImageF img = read_pfm(path);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  const std::vector<float> expect = {0.5f, 0.5f, 0.5f, 2.0f, 2.0f, 2.0f};
  EXPECT_EQ(img.rgb, expect);
}

TEST(ImageIO, TruncatedPfmIsAnError) {
  const std::string path = test::temp_dir() + "/trunc.pfm";
  spit(path, std::string("PF\n2 2\n-1.0\n") + std::string(20, '\0'));
  const std::string msg = error_message([&] { read_pfm(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
}

TEST(ImageIO, ExrRoundTripIsExactFloat) {
  const ImageF hdr = sample_hdr();
  const std::string path = test::temp_dir() + "/round.exr";
  write_image(path, hdr, settings(ToneMap::Reinhard, 0.5f, 2.2f));
  const ImageF back = read_exr(path);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  for (size_t i = 0; i < hdr.rgb.size(); ++i) EXPECT_EQ(back.rgb[i], hdr.rgb[i] * 0.5f) << "index " << i;
  EXPECT_EQ(read_hdr_image(path).rgb, back.rgb);
}

TEST(ImageIO, ExrRoundTripOfACompressedSizedImage) {
  // Large enough that writers which only compress big images take that path.
  ImageF hdr(37, 21);
  for (size_t i = 0; i < hdr.rgb.size(); ++i) hdr.rgb[i] = 0.001f * static_cast<float>(i * i % 9973) + (i % 3);
  const std::string path = test::temp_dir() + "/big.EXR";
  write_image(path, hdr, DisplaySettings{});
  const ImageF back = read_exr(path);
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 21);
  EXPECT_EQ(back.rgb, hdr.rgb);
}

TEST(ImageIO, UnknownExtensionNamesPathAndSupportedFormats) {
  const ImageF hdr(1, 1, 0.5f);
  for (const std::string name : {"out.jpg", "out", "out.ppm.bak"}) {
    const std::string path = test::temp_dir() + "/" + name;
    const std::string msg = error_message([&] { write_image(path, hdr, DisplaySettings{}); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    for (const char* ext : {".ppm", ".png", ".pfm", ".exr"}) EXPECT_NE(msg.find(ext), std::string::npos) << msg;
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

TEST(ImageIO, UnwritablePathIsAnErrorForEveryFormat) {
  const ImageF hdr(2, 2, 0.5f);
  const std::string dir = test::temp_dir() + "/does/not/exist";
  for (const char* ext : {".ppm", ".png", ".pfm", ".exr"}) {
    const std::string path = dir + "/out" + ext;
    const std::string msg = error_message([&] { write_image(path, hdr, DisplaySettings{}); });
    EXPECT_NE(msg.find(path), std::string::npos) << ext << ": " << msg;
  }
}

TEST(ImageIO, EmptyImageIsAnError) {
  const std::string path = test::temp_dir() + "/empty.png";
  EXPECT_THROW(write_image(path, ImageF{}, DisplaySettings{}), Error);
}

TEST(ImageIO, MissingOrCorruptInputNamesTheFile) {
  const std::string dir = test::temp_dir();
  const std::string missing = dir + "/missing.png";
  EXPECT_NE(error_message([&] { read_image8(missing); }).find(missing), std::string::npos);
  EXPECT_NE(error_message([&] { read_pfm(dir + "/missing.pfm"); }).find("missing.pfm"), std::string::npos);
  EXPECT_NE(error_message([&] { read_exr(dir + "/missing.exr"); }).find("missing.exr"), std::string::npos);
  const std::string junk = dir + "/junk.png";
  spit(junk, "this is not an image");
  EXPECT_NE(error_message([&] { read_image8(junk); }).find(junk), std::string::npos);
  EXPECT_NE(error_message([&] { read_pfm(junk); }).find(junk), std::string::npos);
}

// ---- resampling ---------------------------------------------------------

TEST(Resize, BoxHalvesByAveragingBlocks) {
  Image8 src(4, 2);
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y)
      for (int c = 0; c < 3; ++c) src.at(x, y)[c] = static_cast<uint8_t>(10 * (x + 4 * y) + c);
  const Image8 dst = resize_box(src, 2, 1);
  ASSERT_EQ(dst.width, 2);
  ASSERT_EQ(dst.height, 1);
  // Left block: values 0, 10, 40, 50 -> mean 25; right block 20, 30, 60, 70 -> 45.
  EXPECT_EQ(dst.at(0, 0)[0], 25);
  EXPECT_EQ(dst.at(0, 0)[2], 27);
  EXPECT_EQ(dst.at(1, 0)[0], 45);
}

TEST(Resize, BoxWeighsPartialPixelsByArea) {
  Image8 src(3, 1);
  src.rgb = {0, 0, 0, 90, 90, 90, 180, 180, 180};
  const Image8 dst = resize_box(src, 2, 1);
  // Target 0 covers [0, 1.5): (0 * 1 + 90 * 0.5) / 1.5 = 30.
  // Target 1 covers [1.5, 3): (90 * 0.5 + 180 * 1) / 1.5 = 150.
  EXPECT_EQ(dst.at(0, 0)[0], 30);
  EXPECT_EQ(dst.at(1, 0)[0], 150);
}

TEST(Resize, NearestPicksPixelCentres) {
  Image8 src(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) src.at(x, y)[0] = static_cast<uint8_t>(x + 4 * y);
  const Image8 dst = resize_nearest(src, 2, 2);
  EXPECT_EQ(dst.at(0, 0)[0], 5);   // (1, 1)
  EXPECT_EQ(dst.at(1, 0)[0], 7);   // (3, 1)
  EXPECT_EQ(dst.at(0, 1)[0], 13);  // (1, 3)
  EXPECT_EQ(dst.at(1, 1)[0], 15);  // (3, 3)
}

TEST(Resize, BadTargetSizeIsAnError) {
  EXPECT_THROW(resize_box(Image8(2, 2), 0, 1), Error);
  EXPECT_THROW(resize_nearest(Image8(2, 2), 1, -1), Error);
}

// ---- metrics ------------------------------------------------------------

Image8 from_bytes(int w, int h, std::vector<uint8_t> rgb) {
  Image8 img(w, h);
  img.rgb = std::move(rgb);
  return img;
}

TEST(Metrics, BinaryAgreementClassifiesByRed) {
  // Red channels a: 200 128 127 0; b: 255 0 128 255. Classes (R > 127):
  // a: hit hit miss miss; b: hit miss hit hit -> only pixel 0 agrees. Pixel 2
  // straddles the threshold, and a's blue/green must not count as a hit.
  const Image8 a = from_bytes(2, 2, {200, 0, 0, 128, 0, 0, 127, 255, 255, 0, 0, 0});
  const Image8 b = from_bytes(2, 2, {255, 0, 0, 0, 0, 0, 128, 0, 0, 255, 9, 9});
  EXPECT_DOUBLE_EQ(binary_agreement(a, b), 0.25);
  EXPECT_DOUBLE_EQ(binary_agreement(a, a), 1.0);
}

TEST(Metrics, MaskAndIou) {
  const uint8_t bg[3] = {10, 20, 30};
  // Pixel 0 is bg, pixel 1 within tolerance 5, pixel 2 off by 6 in blue, pixel 3 far.
  const Image8 img = from_bytes(4, 1, {10, 20, 30, 15, 15, 35, 10, 20, 36, 200, 0, 0});
  const std::vector<uint8_t> mask = non_background_mask(img, bg, 5);
  EXPECT_EQ(mask, (std::vector<uint8_t>{0, 0, 1, 1}));

  const std::vector<uint8_t> a = {1, 1, 0, 0, 1};
  const std::vector<uint8_t> b = {1, 0, 1, 0, 1};
  EXPECT_DOUBLE_EQ(mask_iou(a, b), 2.0 / 4.0);  // intersection {0, 4}, union {0, 1, 2, 4}
  EXPECT_DOUBLE_EQ(mask_iou(a, a), 1.0);
  EXPECT_DOUBLE_EQ(mask_iou({0, 0}, {0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(mask_iou({1, 0}, {0, 1}), 0.0);
  EXPECT_THROW(mask_iou({1, 0}, {1}), Error);
}

TEST(Metrics, DifferenceStatistics) {
  const Image8 a = from_bytes(2, 1, {0, 0, 0, 100, 100, 100});
  const Image8 b = from_bytes(2, 1, {6, 0, 0, 100, 100, 94});
  // Differences 6, 0, 0, 0, 0, 6: mean 2, rmse sqrt(72 / 6) = sqrt(12), max 6.
  EXPECT_DOUBLE_EQ(mean_abs_diff(a, b), 2.0);
  EXPECT_DOUBLE_EQ(rmse8(a, b), std::sqrt(12.0));
  EXPECT_NEAR(psnr8(a, b), 20.0 * std::log10(255.0 / std::sqrt(12.0)), 1e-12);
  EXPECT_EQ(max_abs_diff(a, b), 6);
  EXPECT_DOUBLE_EQ(mean_abs_diff(a, a), 0.0);
  EXPECT_TRUE(std::isinf(psnr8(a, a)));
}

TEST(Metrics, SizeMismatchIsAnError) {
  const Image8 a(2, 1), b(1, 2);
  EXPECT_THROW(binary_agreement(a, b), Error);
  EXPECT_THROW(mean_abs_diff(a, b), Error);
  EXPECT_THROW(rmse8(a, b), Error);
  EXPECT_THROW(psnr8(a, b), Error);
  EXPECT_THROW(max_abs_diff(a, b), Error);
  EXPECT_THROW(mse(ImageF(2, 1), ImageF(1, 2)), Error);
}

TEST(Metrics, HdrErrors) {
  ImageF ref(1, 1), a(1, 1);
  ref.rgb = {1.0f, 0.0f, 2.0f};
  a.rgb = {2.0f, 0.0f, 2.0f};
  EXPECT_DOUBLE_EQ(mse(a, ref), 1.0 / 3.0);
  EXPECT_NEAR(rel_mse(a, ref, 0.01), (1.0 / 1.01) / 3.0, 1e-12);
  a.rgb[1] = kNaN;
  EXPECT_TRUE(std::isinf(mse(a, ref)));
  EXPECT_TRUE(std::isinf(rel_mse(a, ref)));
}

}  // namespace
}  // namespace caustica
