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

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The per-value errors of the HDR metrics, each defined once here.
struct SquaredError {
  double operator()(double v, double r) const { return (v - r) * (v - r); }
};
struct RelativeSquaredError {
  double eps;
  double operator()(double v, double r) const { return (v - r) * (v - r) / (r * r + eps); }
};
struct AbsoluteError {
  double operator()(double v, double r) const { return std::abs(v - r); }
};
struct IgnorePixels {
  void operator()(size_t, double) const {}
};

// The one walk over two HDR images that every HDR metric shares: hands each
// pixel's channel-mean error to `pixel(index, error)` and returns the mean over
// all values. A NaN anywhere becomes +infinity (see metrics.h).
template <typename Err, typename PixelSink>
double walk_errors(const ImageF& a, const ImageF& ref, const char* what, Err err, PixelSink pixel) {
  check_same_size(a, ref, what);
  const size_t n = a.pixel_count();
  if (n == 0) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* p = &a.rgb[3 * i];
    const float* q = &ref.rgb[3 * i];
    const double e = err(p[0], q[0]) + err(p[1], q[1]) + err(p[2], q[2]);
    pixel(i, std::isnan(e) ? kInfinity : e / 3.0);
    sum += e;
  }
  return std::isnan(sum) ? kInfinity : sum / (3.0 * n);
}

// Calls fn with the per-value error of metric m (relMSE with the default eps).
template <typename Fn>
double with_metric(ErrorMetric m, Fn fn) {
  switch (m) {
    case ErrorMetric::Mse: return fn(SquaredError{});
    case ErrorMetric::RelMse: return fn(RelativeSquaredError{kRelMseEpsilon});
    case ErrorMetric::Mae: return fn(AbsoluteError{});
  }
  throw Error("unknown ErrorMetric value " + std::to_string(static_cast<int>(m)));
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

const char* error_metric_name(ErrorMetric m) {
  switch (m) {
    case ErrorMetric::Mse: return "mse";
    case ErrorMetric::RelMse: return "relmse";
    case ErrorMetric::Mae: return "mae";
  }
  return "?";
}

ErrorMetric parse_error_metric(const std::string& name) {
  for (ErrorMetric m : {ErrorMetric::Mse, ErrorMetric::RelMse, ErrorMetric::Mae})
    if (name == error_metric_name(m)) return m;
  throw Error("unknown error metric '" + name + "' (expected relmse, mse or mae)");
}

double mse(const ImageF& a, const ImageF& ref) { return walk_errors(a, ref, "mse", SquaredError{}, IgnorePixels{}); }

double rel_mse(const ImageF& a, const ImageF& ref, double eps) {
  return walk_errors(a, ref, "rel_mse", RelativeSquaredError{eps}, IgnorePixels{});
}

double mean_abs_error(const ImageF& a, const ImageF& ref) {
  return walk_errors(a, ref, "mean_abs_error", AbsoluteError{}, IgnorePixels{});
}

double mean_error(const ImageF& a, const ImageF& ref, ErrorMetric m) {
  return with_metric(m, [&](auto err) { return walk_errors(a, ref, error_metric_name(m), err, IgnorePixels{}); });
}

std::vector<double> per_pixel_error(const ImageF& a, const ImageF& ref, ErrorMetric m) {
  std::vector<double> out(a.pixel_count());
  with_metric(m, [&](auto err) {
    return walk_errors(a, ref, error_metric_name(m), err, [&](size_t i, double e) { out[i] = e; });
  });
  return out;
}

double psnr_peak(const ImageF& ref) {
  double peak = 0.0;
  for (float v : ref.rgb)
    if (std::isfinite(v)) peak = std::max(peak, double(v));
  return peak > 0.0 ? peak : 1.0;
}

double psnr(const ImageF& a, const ImageF& ref) {
  const double e = mse(a, ref);
  if (e == 0.0) return std::numeric_limits<double>::infinity();
  const double peak = psnr_peak(ref);
  return 10.0 * std::log10(peak * peak / e);  // e = inf gives -inf
}

}  // namespace caustica
