#include "host/render/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <functional>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <cstring>
#include <numeric>
#include <string>

#include "host/error.h"
#include "host/parallel.h"
#include "host/render/error_estimate.h"
#include "host/render/film.h"
#include "host/render/pixel_share.h"

namespace caustica {
namespace {

// Each pixel's weight from its neighbours' per-sample variance, never its
// own: the largest, over the (2 dilate + 1)^2 pixels q around it, of the
// mean of v over the (2 box + 1)^2 pixels around q less the pixel itself.
// A pixel's own samples then decide none of its own count directly (a
// firefly there would otherwise buy it more samples that dilute it: an
// estimate biased low, measured at -1.9% over 24 seeds on a caustic).
// Only rows [first_row, end_row) of the result are computed (the rest stay
// 0): a process of a group computes its band of rows (AdaptiveSampler::
// weights_of), from v over the band and the box and dilation around it.
std::vector<double> neighbours_weight(const std::vector<double>& v, int width, int height, int box, int dilate,
                                      int first_row, int end_row) {
  // Box sums, separable, each summed afresh (no running or summed-area
  // table: one firefly's v, orders of magnitude above its neighbours',
  // would round every later sum of the image).
  // Each pixel of each step on its own, rows shared out to the host's
  // threads (host/parallel.h): the same bits for any thread count, and the
  // device, which waits for this plan, waits less on a many-core host.
  const size_t w = size_t(width);
  std::vector<double> rows(v.size()), sums(v.size());
  std::vector<int> counts(v.size());  // pixels in each box (fewer at the image's edges)
  const auto over_rows = [](int from, int to, const std::function<void(int)>& row) {
    if (to <= from) return;
    parallel_blocks(size_t(to - from), 0, [&](size_t begin, size_t end) {
      for (size_t y = begin; y < end; ++y) row(from + int(y));
    }, 16);
  };
  // The rows each step needs: the output's, the dilation's around them, the
  // box's around those.
  const int sums_from = std::max(0, first_row - dilate), sums_to = std::min(height, end_row + dilate);
  over_rows(std::max(0, sums_from - box), std::min(height, sums_to + box), [&](int y) {
    for (int x = 0; x < width; ++x) {
      double s = 0.0;
      for (int xx = std::max(0, x - box); xx <= std::min(width - 1, x + box); ++xx) s += v[size_t(y) * w + xx];
      rows[size_t(y) * w + x] = s;
    }
  });
  over_rows(sums_from, sums_to, [&](int y) {
    for (int x = 0; x < width; ++x) {
      double s = 0.0;
      for (int yy = std::max(0, y - box); yy <= std::min(height - 1, y + box); ++yy) s += rows[size_t(yy) * w + x];
      const int cols = std::min(width - 1, x + box) - std::max(0, x - box) + 1;
      const int lines = std::min(height - 1, y + box) - std::max(0, y - box) + 1;
      sums[size_t(y) * w + x] = s;
      counts[size_t(y) * w + x] = cols * lines;
    }
  });
  std::vector<double> out(v.size(), 0.0);
  over_rows(first_row, end_row, [&](int y) {
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
  });
  return out;
}

// Real counts to whole ones adding up to `budget`: each rounded down, the
// remainder to the largest fractions (ties: the lower pixel index). The
// pixels that get one more are a selection, not a sort (nth_element: linear
// time; a partial sort of 512^2 pixels took about 60 ms a wave, which a GPU
// spent waiting); the order (fraction, then index) is strict, so the set is
// the same however it is found.
std::vector<uint32_t> round_to_budget(const std::vector<double>& k, uint64_t budget) {
  std::vector<uint32_t> whole(k.size());
  std::vector<double> fraction(k.size());
  uint64_t sum = 0;
  for (size_t p = 0; p < k.size(); ++p) {
    const double down = std::floor(k[p]);
    whole[p] = uint32_t(down);
    fraction[p] = k[p] - down;
    sum += whole[p];
  }
  if (sum >= budget) return whole;  // (never above it: see the caller)
  const size_t remainder = std::min(size_t(budget - sum), k.size());
  std::vector<uint32_t> order(k.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto before = [&](uint32_t a, uint32_t b) {
    return fraction[a] != fraction[b] ? fraction[a] > fraction[b] : a < b;
  };
  if (remainder < order.size()) std::nth_element(order.begin(), order.begin() + remainder, order.end(), before);
  for (size_t i = 0; i < remainder; ++i) ++whole[order[i]];
  return whole;
}

// The smallest double x in [lo, hi] with total(x) >= target, for total
// non-decreasing with total(lo) < target <= total(hi): what bisection down
// to adjacent doubles returns (the bracket keeps that invariant, so its
// end is that x whatever points were tried), in far fewer evaluations.
// total is piecewise linear (the Neyman counts are clamped lines), so the
// Illinois variant of false position (the endpoint kept twice in a row has
// its value halved) gets within rounding of x in a few steps; a point that
// is not strictly inside the bracket falls back to its midpoint, and the
// loop ends when the bracket is two adjacent doubles. Bisection from a
// bracket of 2^k took some 75 evaluations of total, each a pass over every
// pixel (about 140 ms a wave at 512^2).
template <typename Total>
double solve_increasing(Total total, double lo, double hi, double target) {
  double below = total(lo) - target, above = total(hi) - target;  // below < 0 <= above
  int kept = 0;                                                     // -1: lo moved last, +1: hi moved last
  for (int i = 0; i < 2000; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    double x = above > below ? lo + (hi - lo) * (-below / (above - below)) : mid;
    if (!(x > lo && x < hi)) x = mid;
    const double at = total(x) - target;
    if (at >= 0.0) {
      hi = x;
      above = at;
      if (kept == 1) below *= 0.5;
      kept = 1;
    } else {
      lo = x;
      below = at;
      if (kept == -1) above *= 0.5;
      kept = -1;
    }
  }
  return hi;
}

// std::clamp(x, 0.0, cap) for x neither NaN nor -0 (where maxsd and the
// comparison differ), without branches: the compiler keeps std::clamp's
// branches, and on an image's counts they were mispredicted often enough to
// be most of the solver's time.
inline double clamp_without_branches(double x, double cap) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_max_sd(_mm_set_sd(x), _mm_setzero_pd()), _mm_set_sd(cap)));
#else
  return std::clamp(x, 0.0, cap);
#endif
}

}  // namespace

namespace {

// A pixel's per-sample relative variance v = e n, from its estimated
// relMSE e at n samples (a non-finite or negative estimate counts 0).
double per_sample_variance(double e, uint32_t spp) {
  return (std::isfinite(e) ? std::max(0.0, e) : 0.0) * double(spp);
}

// A pixel's cost per sample: rays per sample, at least the camera ray.
double cost_per_sample(uint64_t rays, uint32_t spp) {
  return spp > 0 ? std::max(1.0, double(rays) / double(spp)) : 1.0;
}

// Neyman's weights, before the floor below, of rows [first_row, end_row)
// (the rest 0) from every pixel's v and (empty: every sample costs alike)
// cost per sample: the square root of v filtered and dilated, over the
// neighbours' cost.
std::vector<double> band_weights(int width, int height, const std::vector<double>& v, const std::vector<double>& cost,
                                 const AdaptiveOptions& options, int first_row, int end_row) {
  const int box = std::max(1, options.filter_radius);
  std::vector<double> weight =
      neighbours_weight(v, width, height, box, std::clamp(options.dilate_radius, 0, box), first_row, end_row);
  if (!cost.empty()) {
    // Equal time: weigh v by the cost per sample, its neighbours' mean like
    // v's (no dilation: a costly rim should not make a cheap inside look
    // costly).
    const std::vector<double> neighbours_cost = neighbours_weight(cost, width, height, box, 0, first_row, end_row);
    for (size_t p = size_t(first_row) * size_t(width); p < size_t(end_row) * size_t(width); ++p)
      weight[p] /= std::max(1.0, neighbours_cost[p]);
  }
  for (double& w : weight) w = std::sqrt(w);
  return weight;
}

// A small share of the largest weight keeps every weight positive, so that
// samples the noisy pixels cannot take (their cap) go to the others rather
// than nowhere.
std::vector<double> with_floor(std::vector<double> weight) {
  double largest = 0.0;
  for (double w : weight) largest = std::max(largest, w);
  const double least = largest > 0.0 ? 1e-9 * largest : 1.0;
  for (double& w : weight) w += least;
  return weight;
}

}  // namespace

std::vector<double> neyman_weights(const AdaptiveInputs& in, const AdaptiveOptions& options) {
  const size_t pixels = size_t(in.width) * size_t(in.height);
  if (in.width <= 0 || in.height <= 0 || in.pixel_error.size() != pixels || in.spp.size() != pixels ||
      (!in.rays.empty() && in.rays.size() != pixels))
    throw Error("adaptive sampling: " + std::to_string(in.pixel_error.size()) + " errors, " +
                std::to_string(in.spp.size()) + " counts and " + std::to_string(in.rays.size()) + " ray counts for " +
                std::to_string(in.width) + "x" + std::to_string(in.height) + " pixels");
  std::vector<double> v(pixels), cost;
  for (size_t p = 0; p < pixels; ++p) v[p] = per_sample_variance(in.pixel_error[p], in.spp[p]);
  if (!in.rays.empty()) {
    cost.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) cost[p] = cost_per_sample(in.rays[p], in.spp[p]);
  }
  return with_floor(band_weights(in.width, in.height, v, cost, options, 0, in.height));
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
  // A pixel's count for a Neyman multiplier lambda and a floor: its total
  // after the wave is max(floor, lambda weight), less what it has, within
  // [0, cap]. The solver only sums them (some 15-20 times a wave); the
  // result is kept once.
  const auto count = [&](size_t p, double lambda, double floor_at) {
    const double scaled = lambda * weight[p];
    return clamp_without_branches((floor_at < scaled ? scaled : floor_at) - double(spp[p]), cap);
  };
  const auto total_at = [&](double lambda, double floor_at) {
    double sum = 0.0;
    for (size_t p = 0; p < pixels; ++p) sum += count(p, lambda, floor_at);
    return sum;
  };
  const auto place = [&](double lambda, double floor_at) {
    for (size_t p = 0; p < pixels; ++p) k[p] = count(p, lambda, floor_at);
  };
  const double wanted = double(budget);
  if (total_at(0.0, floor_total) >= wanted) {
    // The floor alone takes the wave: lower it (pixels behind come first).
    place(0.0, solve_increasing([&](double f) { return total_at(0.0, f); }, 0.0, floor_total, wanted));
  } else {
    // A bracket from the counts' scale: with every pixel above the floor
    // and below the cap, lambda sum(weight) = total + budget; twice that,
    // doubled until it holds (the result does not depend on the bracket).
    double weight_sum = 0.0;
    for (double w : weight) weight_sum += w;
    double hi = weight_sum > 0.0 ? std::max(1.0, 2.0 * (double(total) + wanted) / weight_sum) : 1.0;
    while (total_at(hi, floor_total) < wanted && hi < 1e300) hi *= 2.0;
    place(solve_increasing([&](double lambda) { return total_at(lambda, floor_total); }, 0.0, hi, wanted),
          floor_total);
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
  if (needs_weights(film.passes())) {
    weight_ = weights_of(film, options_);
    weights_passes_ = film.passes();
  }
  return place(film.pixel_spp(), pass_count);
}

std::vector<double> AdaptiveSampler::weights_of(const Film& film, const AdaptiveOptions& options, PixelShare* group) {
  AdaptiveInputs in;
  in.width = film.width();
  in.height = film.height();
  in.spp = film.pixel_spp();
  if (!group) {
    in.pixel_error = pixel_rel_mse(film.mean(), film.half_mean(), in.spp, film.half_counts());
    if (options.weigh_cost) in.rays = film.pixel_rays();
    return neyman_weights(in, options);
  }
  // Shared: each process sums, converts and weighs its band of rows
  // (Film::summed_band), and the bands' v and cost per sample are gathered
  // to all in pixel order: the numbers one process computes, each once.
  const Film::Band band = film.summed_band(*group, options.weigh_cost);
  const std::vector<double> error = pixel_rel_mse(band.means.mean, band.means.half, in.spp, film.half_counts());
  const size_t values = options.weigh_cost ? 2 : 1;
  std::vector<double> mine;
  mine.reserve((band.end - band.first) * values);
  for (size_t p = band.first; p < band.end; ++p) {
    mine.push_back(per_sample_variance(error[p], in.spp[p]));
    if (options.weigh_cost) mine.push_back(cost_per_sample(band.rays[p - band.first], in.spp[p]));
  }
  const std::string all = group->gather_bytes_to_all(
      std::string(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(double)));
  const size_t pixels = film.pixel_count();
  if (all.size() != pixels * values * sizeof(double))
    throw Error("adaptive sampling: " + std::to_string(all.size()) + " bytes of per-sample variances gathered for " +
                std::to_string(pixels) + " pixels");
  std::vector<double> both(pixels * values), v(pixels), cost(options.weigh_cost ? pixels : 0);
  std::memcpy(both.data(), all.data(), all.size());
  for (size_t p = 0; p < pixels; ++p) {
    v[p] = both[values * p];
    if (options.weigh_cost) cost[p] = both[values * p + 1];
  }
  // Each process filters its band of rows; the bands' weights, gathered in
  // pixel order, are the image's.
  const auto [first_row, end_row] = share_of(size_t(in.height), group->rank(), group->size());
  const std::vector<double> weight = band_weights(in.width, in.height, v, cost, options, int(first_row), int(end_row));
  const size_t width = size_t(in.width);
  const std::string weights = group->gather_bytes_to_all(
      std::string(reinterpret_cast<const char*>(weight.data() + first_row * width), (end_row - first_row) * width *
                                                                                        sizeof(double)));
  if (weights.size() != pixels * sizeof(double))
    throw Error("adaptive sampling: " + std::to_string(weights.size()) + " bytes of weights gathered for " +
                std::to_string(pixels) + " pixels");
  std::vector<double> whole(pixels);
  std::memcpy(whole.data(), weights.data(), weights.size());
  return with_floor(std::move(whole));
}

std::vector<uint32_t> AdaptiveSampler::place(const std::vector<uint32_t>& spp, int pass_count) const {
  return place_wave_samples(weight_, spp, pass_count, Film::kMostSamplesPerPixel, options_);
}

}  // namespace caustica
