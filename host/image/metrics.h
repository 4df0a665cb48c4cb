// Image comparison. 8-bit metrics judge renders against the coursework's PPM
// references (where exact equality is hopeless across implementations, so
// tests use agreement fractions and thresholds); HDR metrics measure true
// error against a converged linear reference. Every two-image function throws
// caustica::Error when the sizes differ.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/image/image.h"

namespace caustica {

// Fraction of pixels whose hit/miss class agrees, the class being R > 127
// (binary mode draws hits red on a black background).
double binary_agreement(const Image8& a, const Image8& b);

// 1 where any channel differs from bg by more than tolerance, else 0.
std::vector<uint8_t> non_background_mask(const Image8& img, const uint8_t bg[3], int tolerance);
// |a & b| / |a | b| over non-zero entries; 1 when both masks are empty.
double mask_iou(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);

// Over all pixels and channels, in 0..255 units.
double mean_abs_diff(const Image8& a, const Image8& b);
double rmse8(const Image8& a, const Image8& b);
// 20 log10(255 / rmse); +infinity for identical images.
double psnr8(const Image8& a, const Image8& b);
int max_abs_diff(const Image8& a, const Image8& b);

// HDR error of an image `a` against a reference `ref`, each the mean over all
// pixels and channels of one per-value error:
//   MSE     (a - ref)^2
//   relMSE  (a - ref)^2 / (ref^2 + eps), eps = kRelMseEpsilon unless given:
//           relative, so bright regions do not dominate, and eps keeps black
//           reference pixels from dividing by zero
//   MAE     |a - ref|
// Non-finite values count as an infinite error rather than being skipped, so
// a threshold test fails instead of a NaN comparison silently passing.
constexpr double kRelMseEpsilon = 1e-2;

enum class ErrorMetric { Mse, RelMse, Mae };
// "mse", "relmse", "mae"; parse_error_metric throws naming the valid names.
const char* error_metric_name(ErrorMetric m);
ErrorMetric parse_error_metric(const std::string& name);

double mse(const ImageF& a, const ImageF& ref);
double rel_mse(const ImageF& a, const ImageF& ref, double eps = kRelMseEpsilon);
double mean_abs_error(const ImageF& a, const ImageF& ref);
double mean_error(const ImageF& a, const ImageF& ref, ErrorMetric m);

// One value per pixel (row-major, top row first): the metric averaged over
// the pixel's three channels, +infinity where any channel is NaN. The mean of
// these values is mean_error(a, ref, m).
std::vector<double> per_pixel_error(const ImageF& a, const ImageF& ref, ErrorMetric m);

// Peak signal-to-noise ratio in dB, 10 log10(peak^2 / MSE). The peak is the
// reference's largest finite channel value, or 1 when no channel value is
// positive (an all-zero reference): linear HDR images have no fixed white, so
// the reference's own brightest value stands in for 8-bit's 255.
// +infinity for identical images, -infinity when the MSE is infinite.
double psnr(const ImageF& a, const ImageF& ref);
double psnr_peak(const ImageF& ref);

}  // namespace caustica
