// Pixel boxes of an image (a caustic region, say) and the sums and errors
// over them that the caustics tests compare with references.
#pragma once

#include <initializer_list>
#include <vector>

#include "host/image/image.h"
#include "host/image/metrics.h"

namespace caustica::test {

struct PixelBox {
  int x0, x1, y0, y1;  // inclusive, rows from the top
  bool holds(int x, int y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

// fn(index of one value) for every channel of every pixel in the boxes.
template <typename Fn>
void for_each_box_value(const ImageF& img, const std::vector<PixelBox>& boxes, Fn fn) {
  for (const PixelBox& b : boxes)
    for (int y = b.y0; y <= b.y1; ++y)
      for (int x = b.x0; x <= b.x1; ++x)
        for (int c = 0; c < 3; ++c) fn(size_t(3 * (y * img.width + x) + c));
}

// relMSE of img against ref over the boxes (metrics.h's epsilon).
inline double boxes_rel_mse(const ImageF& img, const ImageF& ref, const std::vector<PixelBox>& boxes) {
  double sum = 0.0;
  size_t n = 0;
  for_each_box_value(img, boxes, [&](size_t i) {
    const double d = img.rgb[i] - ref.rgb[i];
    sum += d * d / (double(ref.rgb[i]) * ref.rgb[i] + kRelMseEpsilon);
    ++n;
  });
  return n ? sum / double(n) : 0.0;
}

inline double boxes_sum(const ImageF& img, const std::vector<PixelBox>& boxes) {
  double sum = 0.0;
  for_each_box_value(img, boxes, [&](size_t i) { sum += img.rgb[i]; });
  return sum;
}

inline double image_sum(const ImageF& img) {
  double sum = 0.0;
  for (float v : img.rgb) sum += v;
  return sum;
}

}  // namespace caustica::test
