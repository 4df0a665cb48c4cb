// Adaptive sampling (issue 22): the next wave's samples go where the film's
// own error estimate says they lower the image's relMSE most.
//
// Rules. The estimate is the half buffer's (host/render/error_estimate.h):
// per pixel, e = sum over channels of (M - B)^2 n_B / n_A / (M^2 + eps),
// the pixel's expected relMSE at its n samples. Its per-sample relative
// variance v = e n is what the allocation weighs. Minimising sum v / n
// subject to a fixed total is Neyman's allocation, n proportional to
// sqrt(v) (the Lagrange condition v / n^2 equal everywhere); a wave
// water-fills towards it: every pixel's total after the wave is
// max(floor, lambda sqrt(v)), lambda chosen so that the wave's samples add
// up exactly. At equal time, not equal samples, the rule weighs each
// pixel's cost per sample c too: minimising sum v / n subject to
// sum c n fixed gives n proportional to sqrt(v / c). A pixel's cost is the
// rays its samples traced so far (closest-hit and shadow) over its samples
// (the film's pixel_rays, counted by the shade stage): a glass pixel's long paths cost
// several times a wall's, a miss the least. Cycles' noise-threshold sampling (Dammertz et al. 2009's
// criterion on the same half-buffer difference) switches pixels off at a
// threshold instead; here there is no threshold to choose: the wave's size
// is the pass driver's, only its spread is adaptive.
//
// Guards against a pixel that looks converged because it has not found a
// rare path yet (a caustic seen through a few samples):
//  - no adaptive wave before min_spp samples a pixel (a power of two: the
//    Sobol-Burley prefix is a stratified net and the half a fair one);
//  - v is filtered over (2 filter_radius + 1)^2 pixels (one pixel's
//    estimate is a chi-square of 3 channels: far too noisy to allocate by)
//    and then dilated (a 3x3 maximum, dilate_radius 1), so the rim of a
//    noisy region is sampled like its inside; a pixel's own v is left out
//    of its own weight (below);
//  - a floor: after the wave every pixel has at least uniform_share times
//    the image's mean count (and min_spp), so that share of the samples
//    stays uniform and no pixel is ever left behind for good.
// Everything is a function of the film's bits and the counts, so the same
// seed gives the same allocation, and so the same image, on any machine.
//
// The cost is filtered like v, over the neighbours only (a path's length
// and its radiance are not independent).
//
// Bias: a mean over a count that depends on its own samples is not
// unbiased (Kirk & Arvo 1991): a firefly that buys its pixel more samples
// is diluted, a pixel that has not found its rare path yet stays at the
// floor, and the image runs low (-1.9% over 24 seeds on a path-traced
// caustic when the pixel's own estimate counted). So a pixel's weight is
// its neighbours' per-sample variance, never its own: its count no longer
// follows its own samples, only (through the neighbours' counts, from wave
// to wave) the precision of their estimates, a second-order dependence.
// tests/test_adaptive_sampling.cpp measures the mean over seeds against a
// long uniform render within its standard error.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "host/image/image.h"

namespace caustica {

class Film;
class PixelShare;

struct AdaptiveOptions {
  uint32_t min_spp = 16;        // uniform until every pixel has these (a power of two >= 2)
  double uniform_share = 0.25;  // the floor's share of the mean count
  int filter_radius = 2;        // the per-sample variance's box filter: (2r + 1)^2 pixels
  int dilate_radius = 1;        // then its maximum over (2r + 1)^2 pixels
  bool weigh_cost = true;       // n ~ sqrt(v / c) (equal time), not sqrt(v) (equal samples)
};

// The film's inputs to an allocation, each row-major per pixel.
struct AdaptiveInputs {
  int width = 0, height = 0;
  std::vector<double> pixel_error;  // e: the pixel's estimated relMSE (pixel_rel_mse)
  std::vector<uint32_t> spp;        // n: its samples so far
  std::vector<uint64_t> rays;       // the rays its samples traced (empty: every sample costs alike)
};

// Samples per pixel for a wave of `pass_count` passes: the counts add up to
// pass_count x pixels, each at most `most_per_pixel`. Throws caustica::Error
// on inconsistent sizes.
std::vector<uint32_t> allocate_wave_samples(const AdaptiveInputs& in, int pass_count, uint32_t most_per_pixel,
                                            const AdaptiveOptions& options);

// The two steps: each pixel's Neyman weight (the square root of its
// neighbours' filtered per-sample variance over their cost per sample), and the counts that water-fill
// towards it from the pixels' current counts.
std::vector<double> neyman_weights(const AdaptiveInputs& in, const AdaptiveOptions& options);
std::vector<uint32_t> place_wave_samples(const std::vector<double>& weight, const std::vector<uint32_t>& spp,
                                         int pass_count, uint32_t most_per_pixel, const AdaptiveOptions& options);

// A render's allocations from its film (with the half buffer). It reads the
// film again only when the mean count has grown by a quarter since its
// weights were taken (each read is the mean and the half, and with the
// photon pass its caustic image: a cost per wave that small waves felt),
// and places every wave from the current counts. It depends on the film's
// counts and bits only, so the same seed gives the same plan.
// The sampler's cached weights and the film's pass count when they were
// taken: a resumed render (host/render/render_state.h) restores them, so
// that its waves are placed exactly as an uninterrupted render's.
struct AdaptiveSamplerState {
  std::vector<double> weights;  // empty: none taken yet
  int weights_passes = 0;
};

class AdaptiveSampler {
 public:
  explicit AdaptiveSampler(const AdaptiveOptions& options) : options_(options) {}
  std::vector<uint32_t> plan(const Film& film, int pass_count);
  // The weights plan() takes from a film when it refreshes them. `group`:
  // the film is one of a group of processes that share every wave
  // (pass_driver.h's WaveShare), whose films are summed for them (a
  // collective: Film::summed_means), so every process takes one process's
  // weights and hands them to its sampler with restore().
  static std::vector<double> weights_of(const Film& film, const AdaptiveOptions& options,
                                        PixelShare* group = nullptr);
  // Whether plan() reads the film's estimate again at this many passes
  // (its weights change slowly: again once the samples grew by a quarter).
  bool needs_weights(int film_passes) const {
    return weight_.empty() || film_passes < weights_passes_ || 4 * film_passes >= 5 * weights_passes_;
  }
  // plan() where needs_weights is false: its counts from the pixels' counts
  // alone, so the host can place a wave before the previous one has been
  // traced (PassDriver). Reads only this sampler's weights.
  std::vector<uint32_t> place(const std::vector<uint32_t>& spp, int pass_count) const;
  const AdaptiveOptions& options() const { return options_; }
  AdaptiveSamplerState state() const { return {weight_, weights_passes_}; }
  void restore(AdaptiveSamplerState state) {
    weight_ = std::move(state.weights);
    weights_passes_ = state.weights_passes;
  }

 private:
  AdaptiveOptions options_;
  std::vector<double> weight_;
  int weights_passes_ = 0;
};

}  // namespace caustica
