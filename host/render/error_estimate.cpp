#include "host/render/error_estimate.h"

#include <algorithm>
#include <cmath>

#include "host/error.h"
#include "host/image/metrics.h"

namespace caustica {

namespace {
void check_sizes(const ImageF& mean, const ImageF& half_mean, size_t spp, size_t half_counts) {
  if (mean.width != half_mean.width || mean.height != half_mean.height || mean.rgb.size() != half_mean.rgb.size())
    throw Error("error estimate: the half buffer's size differs from the film's");
  if (spp != mean.pixel_count() || half_counts != mean.pixel_count())
    throw Error("error estimate: " + std::to_string(spp) + " and " + std::to_string(half_counts) +
                " pixel counts for an image of " + std::to_string(mean.pixel_count()) + " pixels");
}
}  // namespace

std::vector<double> pixel_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts) {
  check_sizes(mean, half_mean, spp.size(), half_counts.size());
  std::vector<double> error(spp.size(), 0.0);
  for (size_t p = 0; p < spp.size(); ++p) {
    if (half_counts[p] == 0 || half_counts[p] >= spp[p]) continue;
    const double weight = double(half_counts[p]) / double(spp[p] - half_counts[p]);
    double sum = 0.0;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double m = mean.rgb[i], d = m - half_mean.rgb[i];
      sum += d * d / (m * m + kRelMseEpsilon);
    }
    error[p] = sum * weight;
  }
  return error;
}

std::vector<float> pixel_variance(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                  const std::vector<uint32_t>& half_counts, const ImageF* separate_variance) {
  check_sizes(mean, half_mean, spp.size(), half_counts.size());
  if (separate_variance && separate_variance->rgb.size() != mean.rgb.size())
    throw Error("error estimate: the separate variance's size differs from the film's");
  std::vector<float> variance(spp.size(), 0.0f);
  for (size_t p = 0; p < spp.size(); ++p) {
    double sum = 0.0;
    if (half_counts[p] > 0 && half_counts[p] < spp[p]) {
      const double weight = double(half_counts[p]) / double(spp[p] - half_counts[p]);
      for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
        const double d = double(mean.rgb[i]) - half_mean.rgb[i];
        sum += d * d * weight;
      }
    }
    if (separate_variance)
      for (size_t i = 3 * p; i < 3 * p + 3; ++i) sum += separate_variance->rgb[i];
    variance[p] = float(sum / 3.0);
  }
  return variance;
}

double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                         const std::vector<uint32_t>& half_counts, const ImageF* separate_variance) {
  if (separate_variance && separate_variance->rgb.size() != mean.rgb.size())
    throw Error("error estimate: the separate variance's size differs from the film's");
  double sum = 0.0;
  for (double e : pixel_rel_mse(mean, half_mean, spp, half_counts)) sum += e;
  if (separate_variance)
    for (size_t i = 0; i < mean.rgb.size(); ++i) {
      const double m = mean.rgb[i];
      sum += separate_variance->rgb[i] / (m * m + kRelMseEpsilon);
    }
  return mean.rgb.empty() ? 0.0 : sum / double(mean.rgb.size());
}

namespace {
// Each pixel's point and bound terms, summed over its channels (rules in
// the header).
struct PixelTerms {
  std::vector<double> point, bound;
};

PixelTerms pixel_terms(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                       const std::vector<uint32_t>& half_counts, const ImageF* separate_variance,
                       const ImageF* separate_bias2, float exposure) {
  check_sizes(mean, half_mean, spp.size(), half_counts.size());
  for (const ImageF* separate : {separate_variance, separate_bias2})
    if (separate && separate->rgb.size() != mean.rgb.size())
      throw Error("error estimate: the separate estimate's size differs from the film's");
  const double scale = exposure, scale2 = scale * scale;
  PixelTerms terms{std::vector<double>(spp.size(), 0.0), std::vector<double>(spp.size(), 0.0)};
  for (size_t p = 0; p < spp.size(); ++p) {
    const bool has_half = half_counts[p] > 0 && half_counts[p] < spp[p];
    const double weight = has_half ? double(half_counts[p]) / double(spp[p] - half_counts[p]) : 0.0;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double m = scale * mean.rgb[i], d = m - scale * half_mean.rgb[i], m2 = m * m;
      const double noise = d * d * weight + (separate_variance ? scale2 * separate_variance->rgb[i] : 0.0);
      const double bias2 = separate_bias2 ? scale2 * separate_bias2->rgb[i] : 0.0;
      const double v = noise + bias2, u = noise + kBoundBiasWeight * bias2;
      if (v > 0.0) terms.point[p] += v / (std::max(m2 - v, 0.5 * m2) + kRelMseEpsilon);
      if (u > 0.0) terms.bound[p] += u / (std::max(m2 - 3.0 * u, 0.0) + kRelMseEpsilon);
    }
  }
  return terms;
}
}  // namespace

RelMseEstimate estimate_rel_mse(const ImageF& mean, const ImageF& half_mean, const std::vector<uint32_t>& spp,
                                const std::vector<uint32_t>& half_counts, const ImageF* separate_variance,
                                const ImageF* separate_bias2, float exposure) {
  const PixelTerms terms =
      pixel_terms(mean, half_mean, spp, half_counts, separate_variance, separate_bias2, exposure);
  RelMseEstimate out;
  if (mean.rgb.empty()) return out;
  double point = 0.0, bound = 0.0, bound_squares = 0.0;
  for (size_t p = 0; p < terms.point.size(); ++p) {
    point += terms.point[p];
    bound += terms.bound[p];
    bound_squares += terms.bound[p] * terms.bound[p];
  }
  // The bound's own spread: sum * 1.28 sqrt(2 / n_eff), n_eff = sum^2 /
  // sum of squares, is 1.28 sqrt(2 sum of squares).
  const double spread = 1.28 * std::sqrt(2.0 * bound_squares);
  out.estimate = point / double(mean.rgb.size());
  out.bound = (bound + spread) / double(mean.rgb.size());
  return out;
}

std::vector<double> pixel_rel_mse_estimate(const ImageF& mean, const ImageF& half_mean,
                                           const std::vector<uint32_t>& spp, const std::vector<uint32_t>& half_counts,
                                           const ImageF* separate_variance, const ImageF* separate_bias2,
                                           float exposure) {
  std::vector<double> map =
      pixel_terms(mean, half_mean, spp, half_counts, separate_variance, separate_bias2, exposure).point;
  for (double& e : map) e /= 3.0;
  return map;
}

double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, int passes, int half_passes,
                         const ImageF* separate_variance) {
  if (!(half_passes > 0 && half_passes < passes))
    throw Error("error estimate: needs a half of 1 to passes - 1 passes, got " + std::to_string(half_passes) + " of " +
                std::to_string(passes));
  return estimated_rel_mse(mean, half_mean, std::vector<uint32_t>(mean.pixel_count(), uint32_t(passes)),
                           std::vector<uint32_t>(mean.pixel_count(), uint32_t(half_passes)), separate_variance);
}

}  // namespace caustica
