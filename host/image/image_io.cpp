#include "host/image/image_io.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>  // Debian's libtinyexr.so carries the implementation

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>

#include "host/limits.h"
#include "host/read_file.h"
#include "host/write_file.h"

namespace caustica {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

namespace {

constexpr const char* kSupported = ".ppm, .png, .pfm, .exr";

[[noreturn]] void fail_write(const std::string& path, const std::string& why) {
  throw Error("cannot write image '" + path + "': " + why);
}

[[noreturn]] void fail_read(const std::string& path, const std::string& why) {
  throw Error("cannot read image '" + path + "': " + why);
}

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

template <typename Img>
void check_consistent(const std::string& path, const Img& img) {
  if (img.width <= 0 || img.height <= 0)
    fail_write(path, "image is empty (" + size_str(img.width, img.height) + ")");
  if (img.rgb.size() != img.pixel_count() * 3)
    fail_write(path, "image says " + size_str(img.width, img.height) + " but holds " +
                         std::to_string(img.rgb.size()) + " values");
}

// Replaced atomically, every step checked (host/write_file.h): a full disk
// or a failed write leaves the previous image.
void write_all(const std::string& path, std::string_view bytes) { write_output_file(path, bytes, "image"); }

// Bounded, regular files only (host/read_file.h): its errors name the file.
std::string read_all(const std::string& path) {
  return read_input_file(path, "image", limits::kMaxImageFileBytes);
}

// A declared image size against the limits, before any pixel is allocated.
void check_read_size(const std::string& path, long long w, long long h, size_t file_bytes) {
  using namespace limits;
  if (w <= 0 || h <= 0) fail_read(path, "invalid size " + std::to_string(w) + "x" + std::to_string(h));
  if (w > kMaxImageSide || h > kMaxImageSide || uint64_t(w) * uint64_t(h) > kMaxImagePixels)
    fail_read(path, "declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels, over the image limit of " +
                        std::to_string(kMaxImageSide) + " per side and " + std::to_string(kMaxImagePixels) + " pixels");
  if (uint64_t(w) * uint64_t(h) > kMaxPixelsPerFileByte * uint64_t(file_bytes))
    fail_read(path, "declares " + std::to_string(w) + "x" + std::to_string(h) + " pixels in a file of " +
                        std::to_string(file_bytes) + " bytes: truncated or corrupt");
}

void write_ppm(const std::string& path, const Image8& img) {
  std::string out = "P3\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n255\n";
  out.reserve(out.size() + img.rgb.size() * 4);
  for (size_t i = 0; i < img.rgb.size(); i += 3) {
    out += std::to_string(img.rgb[i]);
    out += ' ';
    out += std::to_string(img.rgb[i + 1]);
    out += ' ';
    out += std::to_string(img.rgb[i + 2]);
    out += '\n';
  }
  write_all(path, out);
}

// Encoded in memory and written by write_all: stbi_write_png ignores the
// results of fwrite and fclose, so a full disk would pass as success.
void write_png(const std::string& path, const Image8& img) {
  std::string png;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &png, img.width, img.height, 3, img.rgb.data(), img.width * 3))
    fail_write(path, "stb_image_write could not encode the PNG");
  write_all(path, png);
}

void put_le32(std::string& out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  for (int b = 0; b < 4; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xffu);
}

void write_pfm(const std::string& path, const ImageF& hdr, float scale) {
  // Negative scale = little-endian; the magnitude is conventionally 1.
  std::string out = "PF\n" + std::to_string(hdr.width) + " " + std::to_string(hdr.height) + "\n-1.0\n";
  out.reserve(out.size() + hdr.rgb.size() * 4);
  for (int y = hdr.height - 1; y >= 0; --y) {  // PFM stores the bottom row first
    const float* row = hdr.at(0, y);
    for (int i = 0; i < hdr.width * 3; ++i) put_le32(out, row[i] * scale);
  }
  write_all(path, out);
}

}  // namespace

// Our own SaveEXR: the library's returns early on a write error without
// freeing its header arrays, so every failed write would leak. Here the
// header and planes live in vectors. Every channel is stored as 32-bit float.
void write_exr_planes(const std::string& path, int width, int height, std::vector<ExrPlane> planes) {
  // OpenEXR wants the channel list sorted by name (B, G, R, then lower case).
  std::sort(planes.begin(), planes.end(), [](const ExrPlane& a, const ExrPlane& b) { return a.name < b.name; });
  const int count = static_cast<int>(planes.size());
  std::vector<unsigned char*> plane_ptrs(planes.size());
  for (int c = 0; c < count; ++c) plane_ptrs[c] = reinterpret_cast<unsigned char*>(planes[c].values.data());

  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = count;
  image.images = plane_ptrs.data();
  image.width = width;
  image.height = height;

  std::vector<EXRChannelInfo> channels(planes.size());
  for (int c = 0; c < count; ++c) {
    std::memset(&channels[c], 0, sizeof(EXRChannelInfo));
    std::strncpy(channels[c].name, planes[c].name.c_str(), sizeof(channels[c].name) - 1);
    channels[c].x_sampling = channels[c].y_sampling = 1;
  }
  // Full float in and out: references keep their precision.
  std::vector<int> pixel_types(planes.size(), TINYEXR_PIXELTYPE_FLOAT), requested(planes.size(), TINYEXR_PIXELTYPE_FLOAT);
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = count;
  header.channels = channels.data();
  header.pixel_types = pixel_types.data();
  header.requested_pixel_types = requested.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  // Encoded in memory and written by write_all: tinyexr's own file writer
  // says only "Cannot write a file", whatever the reason.
  const char* err = nullptr;
  unsigned char* memory = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
  std::unique_ptr<unsigned char, void (*)(void*)> guard(memory, std::free);
  if (size == 0 || !memory) {
    std::string why = err ? err : "tinyexr could not encode the image";
    if (err) FreeEXRErrorMessage(err);
    fail_write(path, why);
  }
  write_all(path, std::string_view(reinterpret_cast<const char*>(memory), size));
}

namespace {

// The R, G and B planes of hdr * scale.
std::vector<ExrPlane> rgb_planes(const ImageF& hdr, float scale) {
  const size_t n = hdr.pixel_count();
  std::vector<ExrPlane> planes{{"R", {}}, {"G", {}}, {"B", {}}};
  for (int c = 0; c < 3; ++c) {
    planes[c].values.resize(n);
    for (size_t i = 0; i < n; ++i) planes[c].values[i] = hdr.rgb[3 * i + c] * scale;
  }
  return planes;
}

void write_exr(const std::string& path, const ImageF& hdr, float scale) {
  write_exr_planes(path, hdr.width, hdr.height, rgb_planes(hdr, scale));
}

// ASCII PPM: '#' comments may appear between any two tokens.
Image8 read_p3(const std::string& path, const std::string& bytes) {
  size_t pos = 2;  // past "P3"
  auto next_int = [&](const char* what) -> long {
    for (;;) {
      while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
      if (pos < bytes.size() && bytes[pos] == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
        continue;
      }
      break;
    }
    size_t start = pos;
    long v = 0;
    while (pos < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[pos]))) {
      v = v * 10 + (bytes[pos] - '0');
      if (v > 1000000000L) fail_read(path, std::string("P3 ") + what + " is out of range");
      ++pos;
    }
    if (pos == start) fail_read(path, std::string("P3 file ends or is malformed where the ") + what + " should be");
    return v;
  };
  const long w = next_int("width"), h = next_int("height"), maxval = next_int("maxval");
  if (w <= 0 || h <= 0 || w > 65535 || h > 65535) fail_read(path, "P3 size " + size_str(w, h) + " is not valid");
  if (maxval <= 0 || maxval > 65535) fail_read(path, "P3 maxval " + std::to_string(maxval) + " is not in 1..65535");
  check_read_size(path, w, h, bytes.size());
  // Each value takes a digit and a separator: the data must be there before it gets memory.
  const size_t values = size_t(w) * size_t(h) * 3;
  if (bytes.size() - std::min(bytes.size(), pos) < 2 * values - 1)
    fail_read(path, "P3 data is truncated: " + size_str(w, h) + " needs at least " + std::to_string(2 * values - 1) +
                        " bytes, file has " + std::to_string(bytes.size() - std::min(bytes.size(), pos)));
  Image8 img(static_cast<int>(w), static_cast<int>(h));
  for (auto& out : img.rgb) {
    const long v = next_int("pixel value");
    if (v > maxval) fail_read(path, "P3 value " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
    out = static_cast<uint8_t>((v * 255 + maxval / 2) / maxval);
  }
  return img;
}

}  // namespace

void check_output_image_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".ppm" && ext != ".png" && ext != ".pfm" && ext != ".exr")
    fail_write(path, "unknown extension '" + ext + "' (supported: " + kSupported + ")");
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::is_directory(dir, ec)) fail_write(path, "the directory '" + dir.string() + "' does not exist");
}

bool is_hdr_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".pfm" || ext == ".exr";
}

void write_image(const std::string& path, const ImageF& hdr, const DisplaySettings& display) {
  const std::string ext = lower_extension(path);
  if (ext != ".ppm" && ext != ".png" && ext != ".pfm" && ext != ".exr")
    fail_write(path, "unknown extension '" + ext + "' (supported: " + kSupported + ")");
  check_consistent(path, hdr);
  validate(display);
  if (ext == ".pfm") return write_pfm(path, hdr, display.exposure_scale);
  if (ext == ".exr") return write_exr(path, hdr, display.exposure_scale);
  write_image8(path, to_display(hdr, display));
}

void write_image8(const std::string& path, const Image8& img) {
  const std::string ext = lower_extension(path);
  if (ext != ".ppm" && ext != ".png")
    fail_write(path, "unknown extension '" + ext + "' for an 8-bit image (supported: .ppm, .png)");
  check_consistent(path, img);
  if (ext == ".ppm") return write_ppm(path, img);
  write_png(path, img);
}

Image8 read_image8(const std::string& path) {
  const std::string bytes = read_all(path);
  if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '3') return read_p3(path, bytes);
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) fail_read(path, "file too large for stb_image");
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int len = static_cast<int>(bytes.size());
  int w = 0, h = 0, n = 0;
  // The header first: stb allocates every pixel it declares before decoding.
  if (!stbi_info_from_memory(data, len, &w, &h, &n)) {
    const char* why = stbi_failure_reason();
    fail_read(path, std::string("stb_image: ") + (why ? why : "unknown error"));
  }
  check_read_size(path, w, h, bytes.size());
  std::unique_ptr<unsigned char, void (*)(void*)> pixels(stbi_load_from_memory(data, len, &w, &h, &n, 3),
                                                         stbi_image_free);
  if (!pixels) {
    const char* why = stbi_failure_reason();
    fail_read(path, std::string("stb_image: ") + (why ? why : "unknown error"));
  }
  Image8 img(w, h);
  std::memcpy(img.rgb.data(), pixels.get(), img.rgb.size());
  return img;
}

ImageF read_pfm(const std::string& path) {
  const std::string bytes = read_all(path);
  size_t pos = 0;
  auto token = [&](const char* what) {
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    size_t start = pos;
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    if (pos == start) fail_read(path, std::string("PFM header ends before the ") + what);
    return bytes.substr(start, pos - start);
  };
  const std::string magic = token("magic");
  int channels = 0;
  if (magic == "PF") channels = 3;
  else if (magic == "Pf") channels = 1;
  else fail_read(path, "not a PFM file (magic '" + magic.substr(0, 8) + "', expected PF or Pf)");
  const std::string ws = token("width"), hs = token("height"), ss = token("scale");
  char* end = nullptr;
  const long w = std::strtol(ws.c_str(), &end, 10);
  if (*end) fail_read(path, "PFM width '" + ws + "' is not an integer");
  const long h = std::strtol(hs.c_str(), &end, 10);
  if (*end) fail_read(path, "PFM height '" + hs + "' is not an integer");
  const double scale = std::strtod(ss.c_str(), &end);
  if (*end || scale == 0.0 || !std::isfinite(scale)) fail_read(path, "PFM scale '" + ss + "' is not a non-zero number");
  if (w <= 0 || h <= 0 || w > 1 << 20 || h > 1 << 20) fail_read(path, "PFM size " + size_str(w, h) + " is not valid");
  check_read_size(path, w, h, bytes.size());
  ++pos;  // exactly one whitespace byte separates the header from the data
  const size_t count = static_cast<size_t>(w) * h * channels;
  if (pos > bytes.size() || bytes.size() - pos < count * 4)
    fail_read(path, "PFM data is truncated: " + size_str(w, h) + " needs " + std::to_string(count * 4) +
                        " bytes, file has " + std::to_string(pos > bytes.size() ? 0 : bytes.size() - pos));
  const bool little = scale < 0;
  ImageF img(static_cast<int>(w), static_cast<int>(h));
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + pos);
  for (long y = h - 1; y >= 0; --y) {  // bottom row first in the file
    for (long x = 0; x < w; ++x) {
      float* px = img.at(static_cast<int>(x), static_cast<int>(y));
      for (int c = 0; c < channels; ++c, p += 4) {
        const uint32_t bits = little ? (uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24)
                                     : (uint32_t(p[3]) | uint32_t(p[2]) << 8 | uint32_t(p[1]) << 16 | uint32_t(p[0]) << 24);
        std::memcpy(&px[c], &bits, 4);
      }
      if (channels == 1) px[1] = px[2] = px[0];
    }
  }
  return img;
}

// What Debian's tinyexr 1.0.1 asserts on instead of reporting (an abort,
// found by fuzz_denoise_inputs): a header "type" attribute other than the
// four OpenEXR names, or one that disagrees with the version field's tiled
// bit. Checked here, before any tinyexr call reads the header: the
// attributes of a single-part header (name, type name, int32 size, value)
// up to its closing null byte, every length bounded by the file.
static void check_exr_header_for_tinyexr(const std::string& path, const std::string& bytes) {
  if (bytes.size() < 8) return;  // tinyexr reports this one itself
  const unsigned char flags = static_cast<unsigned char>(bytes[5]);
  const bool tiled = (flags & 0x02) != 0, multipart = (flags & 0x10) != 0;
  if (multipart) return;  // tinyexr's single-part readers refuse it with a message
  size_t at = 8;
  auto c_string = [&](std::string* out) {
    const size_t end = bytes.find('\0', at);
    if (end == std::string::npos) return false;
    *out = bytes.substr(at, end - at);
    at = end + 1;
    return true;
  };
  for (int attributes = 0; attributes < 4096; ++attributes) {
    if (at >= bytes.size()) return;
    if (bytes[at] == '\0') return;  // the header's end
    std::string name, type;
    if (!c_string(&name) || !c_string(&type) || at + 4 > bytes.size()) return;
    uint32_t size = 0;
    for (int i = 0; i < 4; ++i) size |= uint32_t(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    at += 4;
    if (size > bytes.size() - at) return;  // tinyexr refuses a truncated header itself
    if (name == "type") {
      const std::string value = bytes.substr(at, size).c_str();
      const bool known = value == "scanlineimage" || value == "tiledimage" || value == "deeptile" ||
                         value == "deepscanline";
      if (!known) fail_read(path, "header attribute 'type' is '" + value + "', not an OpenEXR part type");
      const bool wants_tiles = value == "tiledimage" || value == "deeptile";
      if (wants_tiles != tiled)
        fail_read(path, "header attribute 'type' is '" + value + "' but the version field says the image is " +
                            (tiled ? "tiled" : "scanline"));
    }
    at += size;
  }
}

ImageF read_exr(const std::string& path) {
  float* rgba = nullptr;
  int w = 0, h = 0;
  const char* err = nullptr;
  const std::string bytes = read_all(path);
  check_exr_header_for_tinyexr(path, bytes);
  const int rc = LoadEXRFromMemory(&rgba, &w, &h, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), &err);
  if (rc != TINYEXR_SUCCESS) {
    std::string why = err ? err : ("tinyexr error " + std::to_string(rc));
    if (err) FreeEXRErrorMessage(err);
    std::free(rgba);
    fail_read(path, why);
  }
  std::unique_ptr<float, void (*)(void*)> guard(rgba, std::free);
  ImageF img(w, h);
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = rgba[4 * i + c];
  return img;
}

void write_exr_with_spp(const std::string& path, const ImageF& hdr, float exposure_scale,
                        const std::vector<uint32_t>& spp) {
  if (lower_extension(path) != ".exr") fail_write(path, "an image with an spp layer must be .exr");
  check_consistent(path, hdr);
  DisplaySettings display;
  display.exposure_scale = exposure_scale;
  validate(display);
  if (spp.size() != hdr.pixel_count())
    fail_write(path, "the spp layer holds " + std::to_string(spp.size()) + " counts for a " +
                         size_str(hdr.width, hdr.height) + " image of " + std::to_string(hdr.pixel_count()) + " pixels");
  std::vector<ExrPlane> planes = rgb_planes(hdr, exposure_scale);
  // Counts are exact as float up to 2^24 samples per pixel.
  planes.push_back({"spp", std::vector<float>(spp.begin(), spp.end())});
  write_exr_planes(path, hdr.width, hdr.height, std::move(planes));
}

// The header of a single-part scanline EXR's bytes into *header (InitEXRHeader'd
// by the caller, who frees it); `not_scanline` says why another kind is
// refused. Throws naming the file.
static void parse_scanline_header(const std::string& path, const std::string& bytes, const std::string& not_scanline,
                                  EXRVersion* version, EXRHeader* header) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (ParseEXRVersionFromMemory(version, data, bytes.size()) != TINYEXR_SUCCESS) fail_read(path, "not an EXR file");
  check_exr_header_for_tinyexr(path, bytes);
  if (version->tiled || version->multipart || version->non_image) fail_read(path, not_scanline);
  const char* err = nullptr;
  if (const int rc = ParseEXRHeaderFromMemory(header, version, data, bytes.size(), &err); rc != TINYEXR_SUCCESS) {
    std::string why = err ? err : ("tinyexr error " + std::to_string(rc));
    if (err) FreeEXRErrorMessage(err);
    fail_read(path, why);
  }
}

std::vector<std::string> read_exr_channel_names(const std::string& path) {
  const std::string bytes = read_all(path);
  EXRVersion version;
  EXRHeader header;
  InitEXRHeader(&header);
  std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> header_guard(&header, FreeEXRHeader);
  parse_scanline_header(path, bytes, "only single-part scanline EXR files are read", &version, &header);
  std::vector<std::string> names;
  for (int c = 0; c < header.num_channels; ++c) names.emplace_back(header.channels[c].name);
  return names;
}

std::vector<float> read_exr_channel(const std::string& path, const std::string& channel) {
  int width = 0, height = 0;
  return read_exr_channel(path, channel, &width, &height);
}

std::vector<float> read_exr_channel(const std::string& path, const std::string& channel, int* width, int* height) {
  const std::string bytes = read_all(path);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  EXRVersion version;
  EXRHeader header;
  InitEXRHeader(&header);
  std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> header_guard(&header, FreeEXRHeader);
  parse_scanline_header(path, bytes, "channel '" + channel + "' can only be read from a single-part scanline EXR",
                        &version, &header);
  const char* err = nullptr;
  auto fail_tinyexr = [&](int rc) {
    std::string why = err ? err : ("tinyexr error " + std::to_string(rc));
    if (err) FreeEXRErrorMessage(err);
    fail_read(path, why);
  };
  int index = -1;
  for (int c = 0; c < header.num_channels; ++c)
    if (channel == header.channels[c].name) index = c;
  if (index < 0) fail_read(path, "has no channel named '" + channel + "'");
  const EXRBox2i& window = header.data_window;
  check_read_size(path, 1LL + window.max_x - window.min_x, 1LL + window.max_y - window.min_y, bytes.size());
  for (int c = 0; c < header.num_channels; ++c)
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;

  EXRImage image;
  InitEXRImage(&image);
  if (const int rc = LoadEXRImageFromMemory(&image, &header, data, bytes.size(), &err); rc != TINYEXR_SUCCESS)
    fail_tinyexr(rc);
  std::unique_ptr<EXRImage, int (*)(EXRImage*)> image_guard(&image, FreeEXRImage);
  std::vector<float> values(static_cast<size_t>(image.width) * image.height);
  *width = image.width;
  *height = image.height;
  if (header.requested_pixel_types[index] == TINYEXR_PIXELTYPE_UINT) {
    const auto* counts = reinterpret_cast<const uint32_t*>(image.images[index]);
    std::copy(counts, counts + values.size(), values.begin());
  } else {
    std::memcpy(values.data(), image.images[index], values.size() * sizeof(float));
  }
  return values;
}

ImageF read_hdr_image(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".pfm") return read_pfm(path);
  if (ext == ".exr") return read_exr(path);
  fail_read(path, "unknown HDR extension '" + ext + "' (supported: .pfm, .exr)");
}

}  // namespace caustica
