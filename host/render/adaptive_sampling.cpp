#include "host/render/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "host/error.h"
#include "host/render/error_estimate.h"
#include "host/render/film.h"

namespace caustica {
namespace {

// Each pixel's weight from its neighbours' per-sample variance, never its
// own: the largest, over the (2 dilate + 1)^2 pixels q around it, of the
// mean of v over the (2 box + 1)^2 pixels around q less the pixel itself.
// A pixel's own samples then decide none of its own count directly (a
// firefly there would otherwise buy it more samples that dilute it: an
// estimate biased low, measured at -1.9% over 24 seeds on a caustic).
std::vector<double> neighbours_weight(const std::vector<double>& v, int width, int height, int box, int dilate) {
  // Box sums, separable, each summed afresh (no running or summed-area
  // table: one firefly's v, orders of magnitude above its neighbours',
  // would round every later sum of the image).
  const size_t w = size_t(width);
  std::vector<double> rows(v.size()), sums(v.size());
  std::vector<int> counts(v.size());  // pixels in each box (fewer at the image's edges)
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double s = 0.0;
      for (int xx = std::max(0, x - box); xx <= std::min(width - 1, x + box); ++xx) s += v[size_t(y) * w + xx];
      rows[size_t(y) * w + x] = s;
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double s = 0.0;
      for (int yy = std::max(0, y - box); yy <= std::min(height - 1, y + box); ++yy) s += rows[size_t(yy) * w + x];
      const int cols = std::min(width - 1, x + box) - std::max(0, x - box) + 1;
      const int lines = std::min(height - 1, y + box) - std::max(0, y - box) + 1;
      sums[size_t(y) * w + x] = s;
      counts[size_t(y) * w + x] = cols * lines;
    }
  std::vector<double> out(v.size(), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double own = v[size_t(y) * w + x];
      double best = 0.0;
      for (int qy = std::max(0, y - dilate); qy <= std::min(height - 1, y + dilate); ++qy)
        for (int qx = std::max(0, x - dilate); qx <= std::min(width - 1, x + dilate); ++qx) {
          // p lies in q's box (|q - p| <= dilate <= box): leave it out.
          const size_t q = size_t(qy) * w + qx;
          const int n = counts[q] - 1;
          if (n > 0) best = std::max(best, std::max(0.0, sums[q] - own) / n);
        }
      out[size_t(y) * w + x] = best;
    }
  return out;
}

// Real counts to whole ones adding up to `budget`: each rounded down, the
// remainder to the largest fractions (ties: the lower pixel index).
std::vector<uint32_t> round_to_budget(const std::vector<double>& k, uint64_t budget) {
  std::vector<uint32_t> whole(k.size());
  uint64_t sum = 0;
  for (size_t p = 0; p < k.size(); ++p) {
    whole[p] = uint32_t(std::floor(k[p]));
    sum += whole[p];
  }
  if (sum >= budget) return whole;  // (never above it: see the caller)
  std::vector<uint32_t> order(k.size());
  std::iota(order.begin(), order.end(), 0u);
  const size_t remainder = size_t(budget - sum);
  std::partial_sort(order.begin(), order.begin() + std::min(remainder, order.size()), order.end(),
                    [&](uint32_t a, uint32_t b) {
                      const double fa = k[a] - std::floor(k[a]), fb = k[b] - std::floor(k[b]);
                      return fa != fb ? fa > fb : a < b;
                    });
  for (size_t i = 0; i < remainder && i < order.size(); ++i) ++whole[order[i]];
  return whole;
}

// The smallest x in [lo, hi] with total(x) >= target (total non-decreasing
// and continuous), by bisection to the doubles' resolution.
template <typename Total>
double solve_increasing(Total total, double lo, double hi, double target) {
  for (int i = 0; i < 200 && lo < hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (total(mid) >= target ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

std::vector<double> neyman_weights(const AdaptiveInputs& in, const AdaptiveOptions& options) {
  const size_t pixels = size_t(in.width) * size_t(in.height);
  if (in.width <= 0 || in.height <= 0 || in.pixel_error.size() != pixels || in.spp.size() != pixels ||
      (!in.rays.empty() && in.rays.size() != pixels))
    throw Error("adaptive sampling: " + std::to_string(in.pixel_error.size()) + " errors, " +
                std::to_string(in.spp.size()) + " counts and " + std::to_string(in.rays.size()) + " ray counts for " +
                std::to_string(in.width) + "x" + std::to_string(in.height) + " pixels");
  // Per-sample relative variance, filtered and dilated; its square root is
  // Neyman's weight. A small share of the largest keeps every weight
  // positive, so that samples the noisy pixels cannot take (their cap) go
  // to the others rather than nowhere.
  std::vector<double> v(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    const double e = std::isfinite(in.pixel_error[p]) ? std::max(0.0, in.pixel_error[p]) : 0.0;
    v[p] = e * double(in.spp[p]);
  }
  const int box = std::max(1, options.filter_radius);
  std::vector<double> weight = neighbours_weight(v, in.width, in.height, box, std::clamp(options.dilate_radius, 0, box));
  if (!in.rays.empty()) {
    // Equal time: weigh v by the cost per sample, rays per sample (at least
    // the camera ray), its neighbours' mean like v's (no dilation: a costly
    // rim should not make a cheap inside look costly).
    std::vector<double> cost(pixels);
    for (size_t p = 0; p < pixels; ++p)
      cost[p] = in.spp[p] > 0 ? std::max(1.0, double(in.rays[p]) / double(in.spp[p])) : 1.0;
    const std::vector<double> neighbours_cost = neighbours_weight(cost, in.width, in.height, box, 0);
    for (size_t p = 0; p < pixels; ++p) weight[p] /= std::max(1.0, neighbours_cost[p]);
  }
  double largest = 0.0;
  for (double& w : weight) largest = std::max(largest, w = std::sqrt(w));
  const double least = largest > 0.0 ? 1e-9 * largest : 1.0;
  for (double& w : weight) w += least;
  return weight;
}

std::vector<uint32_t> place_wave_samples(const std::vector<double>& weight, const std::vector<uint32_t>& spp,
                                         int pass_count, uint32_t most_per_pixel, const AdaptiveOptions& options) {
  const size_t pixels = spp.size();
  if (weight.size() != pixels)
    throw Error("adaptive sampling: " + std::to_string(weight.size()) + " weights for " + std::to_string(pixels) +
                " pixels");
  if (pass_count < 1 || uint32_t(pass_count) > most_per_pixel)
    throw Error("adaptive sampling: a wave of " + std::to_string(pass_count) + " passes (1 to " +
                std::to_string(most_per_pixel) + ")");
  const uint64_t budget = uint64_t(pass_count) * pixels;
  const double cap = most_per_pixel;
  uint64_t total = 0;
  for (uint32_t n : spp) total += n;
  // The floor: every pixel's total after the wave.
  const double mean_after = double(total + budget) / double(pixels);
  const double floor_total = std::max(double(options.min_spp), std::ceil(options.uniform_share * mean_after));
  std::vector<double> k(pixels);
  auto place = [&](double lambda, double floor_at) {
    double sum = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
      const double target = std::max(floor_at, lambda * weight[p]);
      k[p] = std::clamp(target - double(spp[p]), 0.0, cap);
      sum += k[p];
    }
    return sum;
  };
  const double wanted = double(budget);
  if (place(0.0, floor_total) >= wanted) {
    // The floor alone takes the wave: lower it (pixels behind come first).
    place(0.0, solve_increasing([&](double f) { return place(0.0, f); }, 0.0, floor_total, wanted));
  } else {
    double hi = 1.0;
    while (place(hi, floor_total) < wanted && hi < 1e300) hi *= 2.0;
    place(solve_increasing([&](double lambda) { return place(lambda, floor_total); }, 0.0, hi, wanted), floor_total);
  }
  std::vector<uint32_t> out = round_to_budget(k, budget);
  // Rounding down never leaves more than `budget`; a sum short of it (the
  // bisection's last ulp) was topped up by the largest fractions.
  uint64_t sum = 0;
  for (uint32_t c : out) sum += c;
  if (sum != budget) throw Error("adaptive sampling: placed " + std::to_string(sum) + " of " + std::to_string(budget) + " samples");
  return out;
}

std::vector<uint32_t> allocate_wave_samples(const AdaptiveInputs& in, int pass_count, uint32_t most_per_pixel,
                                            const AdaptiveOptions& options) {
  return place_wave_samples(neyman_weights(in, options), in.spp, pass_count, most_per_pixel, options);
}

std::vector<uint32_t> AdaptiveSampler::plan(const Film& film, int pass_count) {
  // The weights change slowly: read the film (its mean and half, with the
  // photon map's image) again only once its samples grew by a quarter.
  if (weight_.empty() || film.passes() < weights_passes_ || 4 * film.passes() >= 5 * weights_passes_) {
    AdaptiveInputs in;
    in.width = film.width();
    in.height = film.height();
    in.spp = film.pixel_spp();
    in.pixel_error = pixel_rel_mse(film.mean(), film.half_mean(), in.spp, film.half_counts());
    if (options_.weigh_cost) in.rays = film.pixel_rays();
    weight_ = neyman_weights(in, options_);
    weights_passes_ = film.passes();
  }
  return place_wave_samples(weight_, film.pixel_spp(), pass_count, Film::kMostSamplesPerPixel, options_);
}

}  // namespace caustica
