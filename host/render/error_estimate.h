// The film's own estimate of its error, without a reference image.
//
// With M the mean of all N passes and B the mean of the n_B passes in the
// film's half buffer (passes [P, N), P the largest power of two below N;
// the n_A = N - n_B others have mean A), M - B = (n_A / N)(A - B). When the
// two groups are independent estimates of each pixel (variance s^2 per pass),
//   E[(M - B)^2] = (n_A / N)^2 s^2 (1/n_A + 1/n_B) = Var(M) n_A / n_B,
// so (M - B)^2 n_B / n_A estimates Var(M), the MSE of an unbiased M, with no
// reference. Per pixel and channel it is divided by M^2 + eps (eps = 0.01,
// metrics.h's kRelMseEpsilon: pbrt-v4's and the denoising papers' relMSE,
// which keeps near-black pixels from dominating) and averaged.
//
// Assumptions, and what breaks them:
//  - Unbiased passes. A biased estimator (a photon map's radius) converges to
//    its bias, which no difference of passes can see. The photon map's
//    caustic image is no mean of passes at all: it is added to mean and half
//    alike, and its own variance comes in separately (the spread of its
//    passes' estimates, host/render/photon_pass.h); its bias stays unseen.
//  - Independent groups. Sobol-Burley passes are stratified against one
//    another; at N = 2^k the split is into the first and second half of the
//    sequence, each a well-stratified set, so the estimate stays near the
//    truth (an odd/even split measured ~1.8x high on the Cornell box,
//    because odd passes alone are poorly stratified). Between powers of two
//    the half is small and leans toward independent-sample error (high).
//  - The denominator uses M, not the unknown converged value: while M is
//    noisy (a few spp) a firefly inflates M^2 and the estimate runs low, so
//    tests judge it from 8 spp on.
//
// With adaptive sampling every pixel has its own count n and half count
// n_B (Film::half_counts): the same estimate, pixel by pixel, each
// weighted by its own n_B / n_A; a pixel without a half (n_B = 0 or n)
// adds nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "host/image/image.h"

namespace caustica {

// relMSE of `mean` (all `passes`) estimated from `half_mean` (the mean of
// `half_passes` of them, 0 < half_passes < passes). NaN pixels (the film
// never holds any) would make it NaN.
// `separate_variance` (optional, same size): the per-pixel variance of an
// estimate added to both mean and half (the photon map's caustic radiance,
// whose noise the difference of passes cannot see); it adds
// variance / (M^2 + eps) per pixel and channel.
double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, int passes, int half_passes,
                         const ImageF* separate_variance = nullptr);
// The same with each pixel's own counts (`spp` and `half_counts`, one per
// pixel).
double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                         const std::vector<uint32_t>& half_counts, const ImageF* separate_variance = nullptr);
// Each pixel's share of it before the mean over pixels: its three channels'
// (M - B)^2 n_B / n_A / (M^2 + eps), summed (no separate variance).
std::vector<double> pixel_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts);
// Each pixel's estimated variance of its mean, (M - B)^2 n_B / n_A averaged
// over its three channels, plus the separate estimate's variance where given
// (the same mean over channels): the EXR output's "variance.Y" pass. A pixel
// without a half gets 0.
std::vector<float> pixel_variance(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts, const ImageF* separate_variance = nullptr);

}  // namespace caustica
