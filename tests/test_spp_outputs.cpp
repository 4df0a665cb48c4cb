// The outputs of adaptive sampling: the EXR with an "spp" channel beside
// R, G, B (host/image/image_io.h) and the heatmap of the per-pixel sample
// counts (host/app/spp_heatmap.h). The heatmap tests read the PNG back and
// look at its pixels; they need gnuplot and skip without it.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "host/app/gnuplot.h"
#include "host/app/spp_heatmap.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::Contains;

#define REQUIRE_GNUPLOT() \
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed (Debian: gnuplot-nox): skipped"

using test::slurp;

// Neither symmetric nor repeating, so a flipped or transposed read shows.
ImageF ramp_image(int w, int h) {
  ImageF img(w, h);
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.001f * static_cast<float>(i * i % 9973) + (i % 3);
  return img;
}

std::vector<uint32_t> ramp_counts(size_t n) {
  std::vector<uint32_t> spp(n);
  for (size_t i = 0; i < n; ++i) spp[i] = static_cast<uint32_t>(1 + 7 * i);
  return spp;
}

TEST(SppExr, RgbMatchesWriteImageAndSppRoundTrips) {
  const std::string dir = test::temp_dir();
  const ImageF hdr = ramp_image(37, 21);
  const std::vector<uint32_t> spp = ramp_counts(hdr.pixel_count());
  DisplaySettings display;
  display.exposure_scale = 0.5f;
  write_image(dir + "/plain.exr", hdr, display);
  write_exr_with_spp(dir + "/spp.exr", hdr, 0.5f, spp);

  const ImageF plain = read_exr(dir + "/plain.exr"), with_spp = read_exr(dir + "/spp.exr");
  ASSERT_EQ(with_spp.width, 37);
  ASSERT_EQ(with_spp.height, 21);
  EXPECT_EQ(with_spp.rgb, plain.rgb);
  for (size_t i = 0; i < hdr.rgb.size(); ++i) ASSERT_EQ(with_spp.rgb[i], hdr.rgb[i] * 0.5f) << "index " << i;
  for (const char* channel : {"R", "G", "B"})
    EXPECT_EQ(read_exr_channel(dir + "/spp.exr", channel), read_exr_channel(dir + "/plain.exr", channel)) << channel;

  const std::vector<float> counts = read_exr_channel(dir + "/spp.exr", "spp");
  EXPECT_EQ(counts, std::vector<float>(spp.begin(), spp.end()));
}

TEST(SppExr, MissingChannelNamesFileAndChannel) {
  const std::string dir = test::temp_dir();
  write_image(dir + "/plain.exr", ramp_image(4, 3), DisplaySettings{});
  EXPECT_TRUE(Contains(test::error_of([&] { read_exr_channel(dir + "/plain.exr", "spp"); }),
                       {dir + "/plain.exr", "'spp'"}));
  write_exr_with_spp(dir + "/spp.exr", ramp_image(4, 3), 1.0f, ramp_counts(12));
  EXPECT_TRUE(Contains(test::error_of([&] { read_exr_channel(dir + "/spp.exr", "albedo"); }),
                       {dir + "/spp.exr", "'albedo'"}));
  EXPECT_TRUE(Contains(test::error_of([&] { read_exr_channel(dir + "/missing.exr", "spp"); }), {dir + "/missing.exr"}));
}

TEST(SppExr, CountsOfTheWrongSizeAreAnError) {
  const std::string path = test::temp_dir() + "/bad.exr";
  EXPECT_TRUE(Contains(test::error_of([&] { write_exr_with_spp(path, ramp_image(4, 3), 1.0f, ramp_counts(11)); }),
                       {path, "11", "4x3", "12"}));
}

// The layout of draw_heatmap (host/app/gnuplot.cpp): with a title, the map
// starts 16 pixels from the left and 40 from the top, each map pixel drawn as
// a square of ceil(400 / long side) pixels. 64x32 -> 7 pixels per map pixel.
constexpr int kMapW = 64, kMapH = 32, kLeft = 16, kTop = 40, kScale = 7;

// The colour of PNG pixel (px, py); empty (a failure) outside the PNG.
std::vector<uint8_t> png_colour(const Image8& png, int px, int py) {
  if (px < 0 || py < 0 || px >= png.width || py >= png.height) {
    ADD_FAILURE() << "pixel " << px << "," << py << " is outside the " << png.width << "x" << png.height << " PNG";
    return {};
  }
  const uint8_t* p = png.at(px, py);
  return {p[0], p[1], p[2]};
}

// The colour of map pixel (x, y)'s centre in the PNG.
std::vector<uint8_t> colour_at(const Image8& png, int x, int y) {
  return png_colour(png, kLeft + x * kScale + kScale / 2, kTop + y * kScale + kScale / 2);
}

int distance(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

// Left half 16 spp, right half 256: the two halves differ clearly, and a row
// across the boundary holds those two colours only (no smoothing).
TEST(SppHeatmap, FewAndManySamplesDifferInColour) {
  REQUIRE_GNUPLOT();
  const std::string path = test::temp_dir() + "/spp.png";
  std::vector<uint32_t> spp(kMapW * kMapH);
  for (int y = 0; y < kMapH; ++y)
    for (int x = 0; x < kMapW; ++x) spp[y * kMapW + x] = x < kMapW / 2 ? 16 : 256;
  write_spp_heatmap(path, kMapW, kMapH, spp, "spp_map title");
  const Image8 png = read_image8(path);
  ASSERT_GE(png.width, kLeft + kMapW * kScale);
  ASSERT_GE(png.height, kTop + kMapH * kScale);
  EXPECT_LT(png.width, 2 * kMapW * kScale);
  EXPECT_GT(png.width, png.height);

  const std::vector<uint8_t> few = colour_at(png, kMapW / 4, kMapH / 2), many = colour_at(png, 3 * kMapW / 4, kMapH / 2);
  ASSERT_EQ(few.size(), 3u);
  ASSERT_EQ(many.size(), 3u);
  EXPECT_GT(distance(few, many), 150) << "16 spp and 256 spp drawn alike";
  for (int x = 1; x < kMapW - 1; ++x) {
    const std::vector<uint8_t> c = colour_at(png, x, kMapH / 2);
    EXPECT_EQ(c, x < kMapW / 2 ? few : many) << "map pixel " << x;
    EXPECT_EQ(png_colour(png, kLeft + x * kScale, kTop + kMapH / 2 * kScale), c)
        << "map pixel " << x << " is not one colour to its left edge";
  }
}

// Top half 16 spp, bottom half 256: the top of the PNG takes 16's colour.
TEST(SppHeatmap, TopRowIsDrawnAtTheTop) {
  REQUIRE_GNUPLOT();
  const std::string dir = test::temp_dir();
  std::vector<uint32_t> sides(kMapW * kMapH), layers(kMapW * kMapH);
  for (int y = 0; y < kMapH; ++y)
    for (int x = 0; x < kMapW; ++x) {
      sides[y * kMapW + x] = x < kMapW / 2 ? 16 : 256;
      layers[y * kMapW + x] = y < kMapH / 2 ? 16 : 256;
    }
  write_spp_heatmap(dir + "/sides.png", kMapW, kMapH, sides, "sides");
  write_spp_heatmap(dir + "/layers.png", kMapW, kMapH, layers, "layers");
  const Image8 a = read_image8(dir + "/sides.png"), b = read_image8(dir + "/layers.png");
  EXPECT_NE(colour_at(b, kMapW / 2, kMapH / 4), colour_at(b, kMapW / 2, 3 * kMapH / 4));
  EXPECT_EQ(colour_at(b, kMapW / 2, kMapH / 4), colour_at(a, kMapW / 4, kMapH / 2));
  EXPECT_EQ(colour_at(b, kMapW / 2, 3 * kMapH / 4), colour_at(a, 3 * kMapW / 4, kMapH / 2));
}

// gnuplot refuses a colour range of zero width: every pixel at one count
// must still draw, in one colour, as must a map of no samples at all.
TEST(SppHeatmap, UniformMapsStillDraw) {
  REQUIRE_GNUPLOT();
  const std::string dir = test::temp_dir();
  write_spp_heatmap(dir + "/uniform.png", kMapW, kMapH, std::vector<uint32_t>(kMapW * kMapH, 64), "uniform");
  const Image8 png = read_image8(dir + "/uniform.png");
  const std::vector<uint8_t> centre = colour_at(png, kMapW / 2, kMapH / 2);
  EXPECT_NE(centre, (std::vector<uint8_t>{255, 255, 255})) << "nothing drawn";
  EXPECT_EQ(colour_at(png, 1, 1), centre);
  EXPECT_EQ(colour_at(png, kMapW - 2, kMapH - 2), centre);
  write_spp_heatmap(dir + "/zero.svg", 5, 3, std::vector<uint32_t>(15, 0), "no samples");
  EXPECT_TRUE(Contains(slurp(dir + "/zero.svg"), {"<svg", "samples per pixel"}));
}

TEST(SppHeatmap, SizeMismatchNamesBothSizes) {
  const std::string path = test::temp_dir() + "/bad.png";
  EXPECT_TRUE(Contains(test::error_of([&] { write_spp_heatmap(path, 4, 3, std::vector<uint32_t>(11, 1), "t"); }),
                       {path, "11", "4x3", "12"}));
  EXPECT_TRUE(Contains(test::error_of([&] { write_spp_heatmap(path, 0, 3, {}, "t"); }), {path, "0x3"}));
}

}  // namespace
}  // namespace caustica
