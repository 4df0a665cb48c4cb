#include "host/render/error_estimate.h"

#include "host/error.h"
#include "host/image/metrics.h"

namespace caustica {

double estimated_rel_mse(const ImageF& mean, const ImageF& half_mean, int passes, int half_passes) {
  if (!(half_passes > 0 && half_passes < passes))
    throw Error("error estimate: needs a half of 1 to passes - 1 passes, got " + std::to_string(half_passes) + " of " +
                std::to_string(passes));
  if (mean.width != half_mean.width || mean.height != half_mean.height || mean.rgb.size() != half_mean.rgb.size())
    throw Error("error estimate: the half buffer's size differs from the film's");
  const double in_half = half_passes, others = passes - half_passes;
  double sum = 0.0;
  for (size_t i = 0; i < mean.rgb.size(); ++i) {
    const double m = mean.rgb[i], d = m - half_mean.rgb[i];
    sum += d * d / (m * m + kRelMseEpsilon);
  }
  return mean.rgb.empty() ? 0.0 : sum / double(mean.rgb.size()) * (in_half / others);
}

}  // namespace caustica
