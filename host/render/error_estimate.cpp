#include "host/render/error_estimate.h"

#include "host/error.h"
#include "host/image/metrics.h"

namespace caustica {

double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, int passes, int half_passes,
                         const ImageF* separate_variance) {
  if (!(half_passes > 0 && half_passes < passes))
    throw Error("error estimate: needs a half of 1 to passes - 1 passes, got " + std::to_string(half_passes) + " of " +
                std::to_string(passes));
  if (mean.width != half_mean.width || mean.height != half_mean.height || mean.rgb.size() != half_mean.rgb.size())
    throw Error("error estimate: the half buffer's size differs from the film's");
  if (separate_variance && separate_variance->rgb.size() != mean.rgb.size())
    throw Error("error estimate: the separate variance's size differs from the film's");
  const double in_half = half_passes, others = passes - half_passes;
  double sum = 0.0, separate = 0.0;
  for (size_t i = 0; i < mean.rgb.size(); ++i) {
    const double m = mean.rgb[i], d = m - half_mean.rgb[i];
    sum += d * d / (m * m + kRelMseEpsilon);
    if (separate_variance) separate += separate_variance->rgb[i] / (m * m + kRelMseEpsilon);
  }
  return mean.rgb.empty() ? 0.0 : (sum * (in_half / others) + separate) / double(mean.rgb.size());
}

}  // namespace caustica
