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
//
// Rare light (issue 45, docs/error.md). Where a pixel's mean rests on a
// few bright samples (a small light seen through glass, a path-traced
// caustic), the denominator M^2 holds the very firefly whose error it
// should weigh: the true relMSE divides by the converged value mu^2, which
// may be far darker. So the film reports two figures from the same
// per-pixel V = (M - B)^2 n_B / n_A (+ the separate estimate's variance):
//  - the point estimate divides by max(M^2 - V, M^2 / 2) + eps: M^2 - V
//    estimates mu^2 without bias (E[M^2] = mu^2 + Var M), which for a
//    pixel of one hit among dark samples (M = m0 + F/n, V = (F/n)^2) gives
//    m0^2 + 2 m0 F/n, between its dark and its bright value; the floor
//    keeps such a pixel from counting more than 2x its own-mean value (a
//    smooth pixel, V << M^2, stays where it was). 1/2 by measurement
//    (docs/error.md): the medians of every variant stay within 0.53-1.86x
//    of the truth; a floor of 0.4 read 2.03x on stiff_ground at 1024 spp,
//    1/4 2.3x;
//  - the 90% upper bound divides by max(M^2 - 3V, 0) + eps: a pixel whose
//    mean rests on about three samples or fewer (V >= M^2 / 3) could
//    converge to anything from 0 to M, so it is weighed as if dark; and
//    the sum is raised by its own sampling uncertainty, 1 + 1.28
//    sqrt(2 / n_eff), n_eff = (sum e_p)^2 / sum e_p^2 over the pixels'
//    terms (how many pixels the error really rests on: a chi-square sum of
//    n_eff terms has relative deviation sqrt(2 / n_eff); 1.28, the
//    one-sided 90% normal quantile). The photon map's squared bias counts
//    kBoundBiasWeight = 4 times in the bound (it is passed apart from its
//    variance): its Laplacian term read 2.6x low at caustics.json's sharp
//    caustic edges at 1024 passes (1.2x high on stiff_ground's).
// Both are of the image as written: the film times the exposure scale
// (relMSE's eps is not scale-free), which the functions below apply.
// Measured over 16 seeds on scenes/stiff_ground.json, caustics.json, a
// community caustic scene and the Cornell box (docs/error.md), the bound
// covers the true relMSE in at least 90% of renders past 16 spp; the point
// estimate is within 2x of the truth on the median seed wherever the
// photon map carries the caustic, and reads low for path-traced caustics
// at a few hundred spp (a lone firefly's pixel could be dark or bright:
// the truth there is a lottery only the bound covers).
// Adaptive sampling and the caustics balance weigh the classic per-pixel
// estimate (the own-mean denominator), unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "host/image/image.h"

namespace caustica {

// How many times the photon map's squared bias counts in the bound.
constexpr double kBoundBiasWeight = 4.0;

// What the film says of its own relMSE (rules above).
struct RelMseEstimate {
  double estimate = 0.0;  // the point estimate
  double bound = 0.0;     // its 90% upper bound
};
// The film's point estimate and bound, of the film (its mean, half mean
// and each pixel's counts) times `exposure`, with the separate estimate's
// error (optional, the film's size, from Film::separate_error): its
// variance and its squared bias, which the bound weighs kBoundBiasWeight
// times.
RelMseEstimate estimate_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                const std::vector<uint32_t>& half_counts, const ImageF* separate_variance = nullptr,
                                const ImageF* separate_bias2 = nullptr, float exposure = 1.0f);
// Each pixel's point estimate, averaged over its channels: the image's
// mean of it is estimate_rel_mse's point estimate.
std::vector<double> pixel_rel_mse_estimate(const ImageF& mean, const ImageF& half_mean,
                                           const std::vector<uint32_t>& spp, const std::vector<uint32_t>& half_counts,
                                           const ImageF* separate_variance = nullptr,
                                           const ImageF* separate_bias2 = nullptr, float exposure = 1.0f);

// The classic estimate (the own-mean denominator M^2 + eps; what adaptive
// sampling, the caustics balance and the denoiser's guide noise weigh):
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
// Each pixel's share of the classic estimate before the mean over pixels:
// its three channels' (M - B)^2 n_B / n_A / (M^2 + eps), summed (no
// separate variance).
std::vector<double> pixel_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts);
// Each pixel's estimated variance of its mean, (M - B)^2 n_B / n_A averaged
// over its three channels, plus the separate estimate's variance where given
// (the same mean over channels): the EXR output's "variance.Y" pass. A pixel
// without a half gets 0.
std::vector<float> pixel_variance(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts, const ImageF* separate_variance = nullptr);

}  // namespace caustica
