// Image comparison. 8-bit metrics judge renders against the coursework's PPM
// references (where exact equality is hopeless across implementations, so
// tests use agreement fractions and thresholds); HDR metrics measure true
// error against a converged linear reference. Every two-image function throws
// caustica::Error when the sizes differ.
#pragma once

#include <cstdint>
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

// HDR: mean squared error, and relative MSE (a-ref)^2 / (ref^2 + eps) which
// keeps bright regions from dominating. Both over all pixels and channels.
// Non-finite values count as an infinite error rather than being skipped.
double mse(const ImageF& a, const ImageF& ref);
double rel_mse(const ImageF& a, const ImageF& ref, double eps = 1e-2);

}  // namespace caustica
