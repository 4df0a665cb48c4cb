#include "host/image/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace caustica {
namespace {

template <typename Img>
void check_same_size(const Img& a, const Img& b, const char* what) {
  if (a.width != b.width || a.height != b.height)
    throw Error(std::string(what) + ": image sizes differ (" + std::to_string(a.width) + "x" +
                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                "); resize one first");
  if (a.rgb.size() != a.pixel_count() * 3 || b.rgb.size() != b.pixel_count() * 3)
    throw Error(std::string(what) + ": pixel buffer does not match the image size");
}

}  // namespace

double binary_agreement(const Image8& a, const Image8& b) {
  check_same_size(a, b, "binary_agreement");
  const size_t n = a.pixel_count();
  if (n == 0) return 1.0;
  size_t agree = 0;
  for (size_t i = 0; i < n; ++i) agree += (a.rgb[3 * i] > 127) == (b.rgb[3 * i] > 127);
  return static_cast<double>(agree) / n;
}

std::vector<uint8_t> non_background_mask(const Image8& img, const uint8_t bg[3], int tolerance) {
  std::vector<uint8_t> mask(img.pixel_count(), 0);
  for (size_t i = 0; i < mask.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(img.rgb[3 * i + c]) - int(bg[c])) > tolerance) {
        mask[i] = 1;
        break;
      }
  return mask;
}

double mask_iou(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size())
    throw Error("mask_iou: mask sizes differ (" + std::to_string(a.size()) + " vs " + std::to_string(b.size()) + ")");
  size_t inter = 0, uni = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const bool x = a[i] != 0, y = b[i] != 0;
    inter += x && y;
    uni += x || y;
  }
  return uni == 0 ? 1.0 : static_cast<double>(inter) / uni;
}

double mean_abs_diff(const Image8& a, const Image8& b) {
  check_same_size(a, b, "mean_abs_diff");
  if (a.rgb.empty()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return sum / a.rgb.size();
}

double rmse8(const Image8& a, const Image8& b) {
  check_same_size(a, b, "rmse8");
  if (a.rgb.empty()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = int(a.rgb[i]) - int(b.rgb[i]);
    sum += d * d;
  }
  return std::sqrt(sum / a.rgb.size());
}

double psnr8(const Image8& a, const Image8& b) {
  const double e = rmse8(a, b);
  if (e == 0.0) return std::numeric_limits<double>::infinity();
  return 20.0 * std::log10(255.0 / e);
}

int max_abs_diff(const Image8& a, const Image8& b) {
  check_same_size(a, b, "max_abs_diff");
  int m = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) m = std::max(m, std::abs(int(a.rgb[i]) - int(b.rgb[i])));
  return m;
}

double mse(const ImageF& a, const ImageF& ref) {
  check_same_size(a, ref, "mse");
  if (a.rgb.empty()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(ref.rgb[i]);
    sum += d * d;
  }
  // A NaN sum means a NaN pixel: report it as unbounded error so a threshold
  // test fails instead of a NaN comparison silently passing as "not greater".
  return std::isnan(sum) ? std::numeric_limits<double>::infinity() : sum / a.rgb.size();
}

double rel_mse(const ImageF& a, const ImageF& ref, double eps) {
  check_same_size(a, ref, "rel_mse");
  if (a.rgb.empty()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double r = ref.rgb[i];
    const double d = double(a.rgb[i]) - r;
    sum += d * d / (r * r + eps);
  }
  return std::isnan(sum) ? std::numeric_limits<double>::infinity() : sum / a.rgb.size();
}

}  // namespace caustica
