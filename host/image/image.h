// In-memory images. ImageF holds linear HDR radiance as the film produces it;
// Image8 holds display-referred bytes after tone mapping (or as read from a
// PNG/PPM reference). Both are row-major, top row first, 3 channels, so pixel
// (x, y) starts at index 3 * (y * width + x) in either.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/error.h"

namespace caustica {

struct ImageF {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear, 3 floats per pixel

  ImageF() = default;
  ImageF(int w, int h, float fill = 0.0f)
      : width(w), height(h), rgb(static_cast<size_t>(std::max(w, 0)) * std::max(h, 0) * 3, fill) {}

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  bool empty() const { return width <= 0 || height <= 0; }
  float* at(int x, int y) { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
  const float* at(int x, int y) const { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
};

struct Image8 {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 bytes per pixel

  Image8() = default;
  Image8(int w, int h, uint8_t fill = 0)
      : width(w), height(h), rgb(static_cast<size_t>(std::max(w, 0)) * std::max(h, 0) * 3, fill) {}

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  bool empty() const { return width <= 0 || height <= 0; }
  uint8_t* at(int x, int y) { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
  const uint8_t* at(int x, int y) const { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
};

namespace detail {

inline void check_resize(int src_w, int src_h, int w, int h, const char* what) {
  if (w <= 0 || h <= 0 || src_w <= 0 || src_h <= 0)
    throw Error(std::string(what) + ": cannot resize a " + std::to_string(src_w) + "x" +
                std::to_string(src_h) + " image to " + std::to_string(w) + "x" + std::to_string(h) +
                " (both sizes must be positive)");
}

// Exact area weighting, so a 2x reduction is a plain 2x2 mean and
// non-integer ratios (e.g. 300 -> 128) still give every source pixel the
// weight of the area it covers. Works for enlargement too.
template <typename Img, typename Store>
Img resize_box_impl(const Img& src, int w, int h, Store store) {
  check_resize(src.width, src.height, w, h, "resize_box");
  Img dst(w, h);
  const double sx = static_cast<double>(src.width) / w;
  const double sy = static_cast<double>(src.height) / h;
  for (int y = 0; y < h; ++y) {
    const double y0 = y * sy, y1 = (y + 1) * sy;
    const int iy0 = static_cast<int>(std::floor(y0));
    const int iy1 = std::min(src.height, static_cast<int>(std::ceil(y1)));
    for (int x = 0; x < w; ++x) {
      const double x0 = x * sx, x1 = (x + 1) * sx;
      const int ix0 = static_cast<int>(std::floor(x0));
      const int ix1 = std::min(src.width, static_cast<int>(std::ceil(x1)));
      double sum[3] = {0, 0, 0}, total = 0;
      for (int j = iy0; j < iy1; ++j) {
        const double wy = std::min<double>(j + 1, y1) - std::max<double>(j, y0);
        if (wy <= 0) continue;
        for (int i = ix0; i < ix1; ++i) {
          const double wx = std::min<double>(i + 1, x1) - std::max<double>(i, x0);
          if (wx <= 0) continue;
          const double wgt = wx * wy;
          const auto* p = src.at(i, j);
          for (int c = 0; c < 3; ++c) sum[c] += wgt * p[c];
          total += wgt;
        }
      }
      auto* q = dst.at(x, y);
      for (int c = 0; c < 3; ++c) q[c] = store(total > 0 ? sum[c] / total : 0.0);
    }
  }
  return dst;
}

template <typename Img>
Img resize_nearest_impl(const Img& src, int w, int h) {
  check_resize(src.width, src.height, w, h, "resize_nearest");
  Img dst(w, h);
  for (int y = 0; y < h; ++y) {
    const int sy = std::min(src.height - 1, static_cast<int>((y + 0.5) * src.height / h));
    for (int x = 0; x < w; ++x) {
      const int sx = std::min(src.width - 1, static_cast<int>((x + 0.5) * src.width / w));
      std::copy_n(src.at(sx, sy), 3, dst.at(x, y));
    }
  }
  return dst;
}

}  // namespace detail

// Area-average resampling: compare a reduced-size render against a
// full-size reference without the aliasing nearest-neighbour would add.
inline Image8 resize_box(const Image8& src, int w, int h) {
  return detail::resize_box_impl(src, w, h, [](double v) {
    return static_cast<uint8_t>(std::clamp(v + 0.5, 0.0, 255.0));
  });
}
inline ImageF resize_box(const ImageF& src, int w, int h) {
  return detail::resize_box_impl(src, w, h, [](double v) { return static_cast<float>(v); });
}

// Pixel-centre sampling; keeps hard binary edges binary.
inline Image8 resize_nearest(const Image8& src, int w, int h) { return detail::resize_nearest_impl(src, w, h); }
inline ImageF resize_nearest(const ImageF& src, int w, int h) { return detail::resize_nearest_impl(src, w, h); }

}  // namespace caustica
