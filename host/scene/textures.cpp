#include "host/scene/textures.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/packing.hpp>
#include <iterator>
#include <limits>
#include <sstream>
#include <system_error>

#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"

namespace caustica {

namespace fs = std::filesystem;

namespace {

double srgb_eotf(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

const std::array<float, 256>& srgb_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = static_cast<float>(srgb_eotf(i / 255.0));
    return t;
  }();
  return table;
}

// The kernels may be built with -cl-fast-relaxed-math and must never see
// inf/NaN, so out-of-range HDR values are clamped to the largest finite half.
uint16_t to_half(float v) {
  if (!(v >= 0.0f)) v = 0.0f;  // also NaN; negative radiance is meaningless
  return glm::packHalf1x16(std::min(v, 65504.0f));
}


// A declared size against the limits (host/limits.h), before any pixel is
// allocated. Returns "" when it may be decoded, else the reason.
// The most pixels `data` can hold in its format (host/limits.h).
uint64_t max_pixels_per_byte(const std::string& data) {
  using namespace limits;
  if (data.size() >= 26 && data.compare(0, 8, "\x89PNG\r\n\x1a\n", 8) == 0) {
    // deflate's 1032:1 over the bits of one pixel (IHDR: bit depth, colour type)
    const int depth = static_cast<unsigned char>(data[24]), type = static_cast<unsigned char>(data[25]);
    const int channels = type == 2 ? 3 : type == 4 ? 2 : type == 6 ? 4 : 1;
    const int bits = std::max(1, depth * channels);
    return std::min<uint64_t>(kMaxPixelsPerFileByte, 1032 * 8 / bits + 1);
  }
  const bool jpeg = data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0xFF &&
                    static_cast<unsigned char>(data[1]) == 0xD8;
  const bool gif = data.compare(0, 4, "GIF8") == 0;
  const bool pnm = data.size() >= 2 && data[0] == 'P' && std::strchr("2356", data[1]) && data[1] != 0;
  return jpeg || gif || pnm ? kMaxPixelsPerFileByte : kMaxPixelsPerFileByteRle;
}

std::string check_texture_size(long long w, long long h, const std::string& data) {
  const size_t file_bytes = data.size();
  using namespace limits;
  const std::string size = std::to_string(w) + " x " + std::to_string(h);
  if (w <= 0 || h <= 0) return "invalid size " + size;
  if (w > kMaxTextureSide || h > kMaxTextureSide || uint64_t(w) * uint64_t(h) > kMaxTexturePixels)
    return "declares " + size + " pixels, over the texture limit of " + std::to_string(kMaxTextureSide) +
           " per side and " + std::to_string(kMaxTexturePixels) + " pixels";
  const uint64_t ratio = max_pixels_per_byte(data);
  if (uint64_t(w) * uint64_t(h) > ratio * uint64_t(file_bytes))
    return "declares " + size + " pixels in a file of " + std::to_string(file_bytes) + " bytes (its format packs " +
           std::to_string(ratio) + " pixels per byte at most: truncated or corrupt)";
  return "";
}

// Netpbm P2/P3/P5/P6 with any maxval. stb reads only the binary kinds and
// takes maxval literally (a maxval-15 file would come out nearly black), so
// the whole family is read here. Returns "" on success, else the reason.
std::string read_pnm(const std::string& data, LinearImage& out) {
  size_t pos = 0;
  auto skip_space_and_comments = [&] {
    while (pos < data.size()) {
      if (data[pos] == '#') {
        while (pos < data.size() && data[pos] != '\n' && data[pos] != '\r') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(data[pos]))) {
        ++pos;
      } else {
        break;
      }
    }
  };
  auto read_uint = [&](long& value) {
    skip_space_and_comments();
    if (pos >= data.size() || !std::isdigit(static_cast<unsigned char>(data[pos]))) return false;
    value = 0;
    while (pos < data.size() && std::isdigit(static_cast<unsigned char>(data[pos]))) {
      value = value * 10 + (data[pos++] - '0');
      if (value > 1000000000L) return false;
    }
    return true;
  };
  if (data.size() < 2 || data[0] != 'P') return "not a PNM file";
  const char kind = data[1];
  if (kind != '2' && kind != '3' && kind != '5' && kind != '6') return std::string("unsupported PNM kind P") + kind;
  pos = 2;
  long w = 0, h = 0, maxval = 0;
  if (!read_uint(w) || !read_uint(h) || !read_uint(maxval)) return "malformed PNM header";
  if (w <= 0 || h <= 0 || maxval <= 0 || maxval > 65535) return "invalid PNM size or maxval";
  if (std::string why = check_texture_size(w, h, data); !why.empty()) return why;
  const int channels = (kind == '3' || kind == '6') ? 3 : 1;
  const size_t count = static_cast<size_t>(w) * h * channels;
  // The data must be there before it is given memory: binary values take 1
  // or 2 bytes each, ASCII ones at least a digit and a separator.
  const size_t left = data.size() - std::min(data.size(), pos + 1);
  const bool ascii = kind == '2' || kind == '3';
  const size_t need = ascii ? 2 * count - 1 : count * (maxval > 255 ? 2 : 1);
  if (left < need)
    return "truncated PNM data: " + std::to_string(w) + " x " + std::to_string(h) + " needs " +
           (ascii ? "at least " : "") + std::to_string(need) + " bytes, the file has " + std::to_string(left);
  std::vector<long> values(count);
  if (kind == '2' || kind == '3') {
    for (size_t i = 0; i < count; ++i)
      if (!read_uint(values[i]) || values[i] > maxval) return "malformed or truncated PNM data";
  } else {
    ++pos;  // exactly one whitespace byte separates the header from binary data
    const size_t bytes = maxval > 255 ? 2 : 1;
    if (data.size() < pos + count * bytes) return "truncated PNM data";
    for (size_t i = 0; i < count; ++i) {
      const auto* p = reinterpret_cast<const unsigned char*>(data.data() + pos + i * bytes);
      values[i] = bytes == 2 ? (p[0] << 8 | p[1]) : p[0];
      if (values[i] > maxval) values[i] = maxval;
    }
  }
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  out.rgb.resize(static_cast<size_t>(w) * h * 3);
  for (size_t t = 0; t < static_cast<size_t>(w) * h; ++t)
    for (int c = 0; c < 3; ++c) {
      const long v = values[t * channels + (channels == 3 ? c : 0)];
      out.rgb[t * 3 + c] = maxval == 255 ? srgb_table()[v] : static_cast<float>(srgb_eotf(double(v) / maxval));
    }
  return "";
}

// Debian's stb_image is built with its assertions on, and its JPEG decoder
// asserts (aborting the process) when a scan uses a Huffman table the file
// never defined: a corrupt texture must be an error, not a crash (found by
// fuzz_texture). This walks the JPEG's markers as stb would and checks that
// every scan's DC and AC tables were defined before it (a progressive DC
// scan needs only DC tables, an AC scan only AC ones; a DC refinement
// none). Returns why the file is corrupt, or "" (stb checks the rest).
std::string check_jpeg_huffman_tables(const std::string& data) {
  const auto* b = reinterpret_cast<const unsigned char*>(data.data());
  const size_t n = data.size();
  // stb takes fill bytes (0xFF) before the start-of-image marker too.
  size_t start = 0;
  while (start + 1 < n && b[start] == 0xFF && b[start + 1] == 0xFF) ++start;
  if (n < start + 4 || b[start] != 0xFF || b[start + 1] != 0xD8) return "";
  bool defined[2][4] = {};
  bool progressive = false;
  size_t at = start + 2;
  while (at + 4 <= n) {
    if (b[at] != 0xFF) {  // padding between segments: stb scans past it to the next marker
      ++at;
      continue;
    }
    const unsigned marker = b[at + 1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0xD9) return "";  // end of image
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {
      at += 2;
      continue;
    }
    const size_t length = (size_t(b[at + 2]) << 8) | b[at + 3];
    if (length < 2 || at + 2 + length > n) return "";
    const unsigned char* seg = b + at + 4;
    const size_t seg_len = length - 2;
    if (marker == 0xC2) progressive = true;
    if (marker == 0xC4) {  // DHT: one or more tables
      for (size_t p = 0; p + 17 <= seg_len;) {
        const unsigned cls = seg[p] >> 4, id = seg[p] & 15;
        size_t count = 0;
        for (int i = 1; i <= 16; ++i) count += seg[p + i];
        if (cls < 2 && id < 4) defined[cls][id] = true;
        // A DC symbol is a coefficient's bit count: stb reads a mask table
        // of 17 entries with it unchecked (found by fuzz_texture).
        if (cls == 0)
          for (size_t i = 0; i < count && p + 17 + i < seg_len; ++i)
            if (seg[p + 17 + i] > 15) return "corrupt JPEG: a DC Huffman table holds a symbol above 15";
        p += 17 + count;
      }
    } else if (marker == 0xDA) {  // SOS: components, then Ss, Se, Ah/Al
      if (seg_len < 1) return "";
      const size_t components = seg[0];
      if (seg_len < 1 + 2 * components + 3) return "";
      const unsigned ss = seg[1 + 2 * components], ah = seg[3 + 2 * components] >> 4;
      const bool needs_dc = !progressive || (ss == 0 && ah == 0), needs_ac = !progressive || ss > 0;
      for (size_t c = 0; c < components; ++c) {
        const unsigned dc = seg[2 + 2 * c] >> 4, ac = seg[2 + 2 * c] & 15;
        if ((needs_dc && (dc > 3 || !defined[0][dc])) || (needs_ac && (ac > 3 || !defined[1][ac])))
          return "corrupt JPEG: a scan uses a Huffman table the file does not define";
      }
      // Entropy-coded data up to the next marker (FF 00 is a byte, FF D0-D7 a restart).
      at += 2 + length;
      while (at + 1 < n && !(b[at] == 0xFF && b[at + 1] != 0x00 && !(b[at + 1] >= 0xD0 && b[at + 1] <= 0xD7))) ++at;
      continue;
    }
    at += 2 + length;
  }
  return "";
}

}  // namespace

std::string decode_texture_image(const std::string& data, LinearImage& out) {
  if (data.size() >= 2 && data[0] == 'P' && std::strchr("2356", data[1]) && data[1] != 0) return read_pnm(data, out);
  if (data.size() > size_t(std::numeric_limits<int>::max())) return "file too large for stb_image";
  const auto* bytes = reinterpret_cast<const stbi_uc*>(data.data());
  const int len = static_cast<int>(data.size());
  int w = 0, h = 0, n = 0;
  // The header first: stb allocates every pixel it declares before decoding.
  if (!stbi_info_from_memory(bytes, len, &w, &h, &n)) {
    // stb refuses a PNG beyond its own limits and then reports the last
    // format it tried ("unknown image type"); say which limit it was.
    if (data.size() >= 24 && data.compare(0, 8, "\x89PNG\r\n\x1a\n", 8) == 0 && data.compare(12, 4, "IHDR") == 0) {
      auto be32 = [&](size_t at) {
        return (uint32_t(bytes[at]) << 24) | (uint32_t(bytes[at + 1]) << 16) | (uint32_t(bytes[at + 2]) << 8) |
               uint32_t(bytes[at + 3]);
      };
      if (std::string why = check_texture_size(be32(16), be32(20), data); !why.empty()) return why;
    }
    return stbi_failure_reason() ? stbi_failure_reason() : "unknown image format";
  }
  if (std::string why = check_texture_size(w, h, data); !why.empty()) return why;
  if (std::string why = check_jpeg_huffman_tables(data); !why.empty()) return why;
  if (stbi_is_hdr_from_memory(bytes, len)) {
    float* pixels = stbi_loadf_from_memory(bytes, len, &w, &h, &n, 3);
    if (!pixels) return stbi_failure_reason() ? stbi_failure_reason() : "unknown stb_image error";
    out.width = w, out.height = h;
    out.rgb.assign(pixels, pixels + static_cast<size_t>(w) * h * 3);
    stbi_image_free(pixels);
    return "";
  }
  // Grey + alpha and RGBA images keep their alpha (linear: codes / 255).
  const int channels = n == 2 || n == 4 ? 4 : 3;
  unsigned char* pixels = stbi_load_from_memory(bytes, len, &w, &h, &n, channels);
  if (!pixels) return stbi_failure_reason() ? stbi_failure_reason() : "unknown stb_image error";
  out.width = w, out.height = h;
  const size_t count = static_cast<size_t>(w) * h;
  out.rgb.resize(count * 3);
  if (channels == 4) out.alpha.resize(count);
  for (size_t t = 0; t < count; ++t) {
    for (size_t c = 0; c < 3; ++c) out.rgb[t * 3 + c] = srgb_table()[pixels[t * size_t(channels) + c]];
    if (channels == 4) out.alpha[t] = pixels[t * 4 + 3] / 255.0f;
  }
  stbi_image_free(pixels);
  return "";
}

namespace {

std::string read_image(const std::string& path, LinearImage& out) {
  std::string data;
  try {
    data = read_input_file(path, "texture", limits::kMaxImageFileBytes);
  } catch (const Error& e) {
    // The message names the path already; the caller names it again.
    const std::string what = e.what();
    return what.rfind(path + ": ", 0) == 0 ? what.substr(path.size() + 2) : what;
  }
  return decode_texture_image(data, out);
}

// The last component of a path written on any system: scenes carry
// "C:\Users\...\wood.png" as often as "/home/.../wood.png".
std::string file_name_of(const std::string& written) {
  const size_t cut = written.find_last_of("/\\");
  return cut == std::string::npos ? written : written.substr(cut + 1);
}

std::string executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

}  // namespace

float srgb_byte_to_linear(unsigned char value) { return srgb_table()[value]; }

glm::vec3 mean_texel(const Scene& scene, int index) {
  const Texture& t = scene.textures.at(size_t(index));
  if (t.kind == TEXTURE_CHECKER) return 0.5f * (to_vec3(t.color1) + to_vec3(t.color2));
  glm::dvec3 sum(0.0);
  const size_t n = size_t(t.width) * t.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) sum[c] += glm::unpackHalf1x16(scene.texels.at((size_t(t.offset) + i) * 4 + size_t(c)));
  return n > 0 ? glm::vec3(sum / double(n)) : glm::vec3(0.0f);
}

std::vector<std::string> texture_search_candidates(const std::string& written, const std::string& scene_dir) {
  std::vector<std::string> out;
  auto add = [&](const fs::path& p) {
    const std::string s = p.lexically_normal().string();
    if (!s.empty() && std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  };
  if (written.empty()) return out;
  const fs::path base = scene_dir.empty() ? fs::path(".") : fs::path(scene_dir);
  const fs::path as_written(written);
  add(as_written.is_absolute() ? as_written : base / as_written);
  // A relative Windows path ("textures\wood.png") means the same folders.
  if (written.find('\\') != std::string::npos && written.find(':') == std::string::npos) {
    std::string slashed = written;
    std::replace(slashed.begin(), slashed.end(), '\\', '/');
    if (!slashed.empty() && slashed[0] != '/') add(base / slashed);
  }
  const std::string name = file_name_of(written);
  if (name.empty() || name == "." || name == "..") return out;
  add(base / name);
  add(base / "textures" / name);
#ifdef CAUSTICA_TEXTURE_DIR
  add(fs::path(CAUSTICA_TEXTURE_DIR) / name);
#endif
  const std::string exe_dir = executable_dir();
  if (!exe_dir.empty()) add(fs::path(exe_dir) / ".." / "textures" / name);
  return out;
}

std::string resolve_texture_path(const std::string& written, const std::string& scene_dir) {
  for (const std::string& candidate : texture_search_candidates(written, scene_dir))
    if (is_file(candidate)) {
      std::error_code ec;
      // One key per file however it was reached, so each file loads once.
      const fs::path canonical = fs::weakly_canonical(candidate, ec);
      return ec ? candidate : canonical.string();
    }
  return "";
}

int TextureLibrary::image(const std::string& written, const std::string& scene_dir, const std::string& context,
                          std::vector<std::string>& warnings) {
  const std::string path = resolve_texture_path(written, scene_dir);
  std::string reason;
  if (path.empty()) {
    std::string looked;
    for (const std::string& c : texture_search_candidates(written, scene_dir)) looked += (looked.empty() ? "" : ", ") + c;
    warnings.push_back(context + ": texture \"" + written + "\" not found (looked in: " +
                       (looked.empty() ? std::string("nowhere: empty path") : looked) +
                       "); using a magenta/black checker");
  } else {
    if (auto it = by_path_.find(path); it != by_path_.end()) return it->second;
    if (auto it = failed_.find(path); it != failed_.end()) {
      reason = it->second;
    } else {
      LinearImage img;
      reason = read_image(path, img);
      int index = -1;
      if (reason.empty()) reason = add_image(path, img, &index);
      if (reason.empty()) return index;
      failed_[path] = reason;
    }
    warnings.push_back(context + ": texture \"" + written + "\" (" + path + ") cannot be read: " + reason +
                       "; using a magenta/black checker");
  }
  return fallback();
}

int TextureLibrary::fallback() {
  if (fallback_ < 0) fallback_ = checker(glm::vec3(1.0f, 0.0f, 1.0f), glm::vec3(0.0f), 8.0f);
  return fallback_;
}

std::string TextureLibrary::add_image(const std::string& key, const LinearImage& img, int* index) {
  if (auto it = by_path_.find(key); it != by_path_.end()) {
    *index = it->second;
    return "";
  }
  if (img.width <= 0 || img.height <= 0) return "empty image";
  const size_t first = scene_.texels.size() / 4;
  const size_t count = static_cast<size_t>(img.width) * img.height;
  if (first + count > 0xFFFFFFFFull) return "the scene's texel buffer would exceed 2^32 texels";
  scene_.texels.reserve(scene_.texels.size() + count * 4);
  const uint16_t one = glm::packHalf1x16(1.0f);
  for (size_t t = 0; t < count; ++t) {
    for (int c = 0; c < 3; ++c) scene_.texels.push_back(to_half(img.rgb[t * 3 + c]));
    scene_.texels.push_back(img.alpha.empty() ? one : to_half(img.alpha[t]));
  }
  Texture tex{};
  tex.kind = TEXTURE_IMAGE;
  tex.offset = static_cast<cs_uint>(first);
  tex.width = static_cast<cs_uint>(img.width);
  tex.height = static_cast<cs_uint>(img.height);
  tex.scale = 1.0f;
  scene_.textures.push_back(tex);
  *index = static_cast<int>(scene_.textures.size() - 1);
  by_path_[key] = *index;
  return "";
}

int TextureLibrary::sampled(int base, cs_uint sampling, const glm::vec3& uv_u, const glm::vec3& uv_v) {
  if (sampling == 0u || base < 0 || scene_.textures[size_t(base)].kind != TEXTURE_IMAGE) return base;
  const std::vector<float> key = {float(base), float(sampling), uv_u.x, uv_u.y, uv_u.z, uv_v.x, uv_v.y, uv_v.z};
  if (auto it = sampled_.find(key); it != sampled_.end()) return it->second;
  Texture tex = scene_.textures[size_t(base)];
  tex.sampling = sampling;
  if (sampling & TEXTURE_TRANSFORMED) {
    tex.uv_u = to_float4(uv_u);
    tex.uv_v = to_float4(uv_v);
  }
  scene_.textures.push_back(tex);
  return sampled_[key] = static_cast<int>(scene_.textures.size() - 1);
}

int TextureLibrary::checker(const glm::vec3& color1, const glm::vec3& color2, float scale) {
  Texture tex{};
  tex.kind = TEXTURE_CHECKER;
  tex.color1 = to_float4(color1);
  tex.color2 = to_float4(color2);
  tex.scale = scale;
  scene_.textures.push_back(tex);
  return static_cast<int>(scene_.textures.size() - 1);
}

}  // namespace caustica
