// Adaptive sampling (issue 22; host/render/adaptive_sampling.h): the
// allocation on synthetic errors (it adds up, keeps its floor, follows
// Neyman's sqrt rule, leaves a noise-free region at the floor), then on
// renders: a noise-free half of an image gets only the minimum, the mean
// over seeds matches a long uniform reference within its standard error
// where the allocation stopped pixels early and where it piled samples on,
// and the same seed gives the same bits for any work-group size or slot
// count. (The film's own error estimate with adaptive sampling is checked
// against the truth in tests/test_error_report.cpp: its Sobol-Burley report
// renders adaptively.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/image/metrics.h"
#include "host/render/adaptive_sampling.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::PathRender;
using test::PathRenderOptions;
using test::render_path;
using test::write_scene;

AdaptiveInputs uniform_inputs(int width, int height, uint32_t spp, double error) {
  AdaptiveInputs in;
  in.width = width;
  in.height = height;
  in.spp.assign(size_t(width) * height, spp);
  in.pixel_error.assign(size_t(width) * height, error);
  return in;
}

uint64_t sum(const std::vector<uint32_t>& v) { return std::accumulate(v.begin(), v.end(), uint64_t(0)); }

TEST(AdaptiveAllocation, AddsUpToTheWaveWithinTheCapAndAboveTheFloor) {
  std::mt19937 rng(7);
  std::exponential_distribution<double> heavy(1.0);
  AdaptiveInputs in = uniform_inputs(37, 23, 16, 0.0);
  for (double& e : in.pixel_error) e = std::pow(heavy(rng), 3.0) * 1e-3;  // heavy-tailed, a few huge
  AdaptiveOptions options;
  for (int passes : {1, 3, 16, 64}) {
    const std::vector<uint32_t> k = allocate_wave_samples(in, passes, 128, options);
    ASSERT_EQ(k.size(), in.spp.size());
    EXPECT_EQ(sum(k), uint64_t(passes) * k.size()) << passes;
    const double mean_after = 16.0 + passes;
    const uint32_t floor_total = uint32_t(std::max(16.0, std::ceil(options.uniform_share * mean_after)));
    for (size_t p = 0; p < k.size(); ++p) {
      EXPECT_LE(k[p], 128u);
      EXPECT_GE(in.spp[p] + k[p], std::min(floor_total, in.spp[p] + uint32_t(passes))) << p;
    }
  }
  // The same inputs give the same counts (the render's bits depend on them).
  EXPECT_EQ(allocate_wave_samples(in, 16, 128, options), allocate_wave_samples(in, 16, 128, options));
}

TEST(AdaptiveAllocation, TotalsFollowTheSquareRootOfThePerSampleVariance) {
  // Left half: per-sample variance 16x the right's. Neyman: totals 4:1, as
  // long as the floor (a quarter of the mean) does not bind.
  const int w = 64, h = 32;
  AdaptiveInputs in = uniform_inputs(w, h, 16, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) in.pixel_error[size_t(y) * w + x] = x < w / 2 ? 16e-3 : 1e-3;
  const std::vector<uint32_t> k = allocate_wave_samples(in, 64, 128, AdaptiveOptions{});
  double left = 0, right = 0;
  int nl = 0, nr = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double total = 16.0 + k[size_t(y) * w + x];
      if (x < w / 2 - 3) left += total, ++nl;
      if (x >= w / 2 + 3) right += total, ++nr;
    }
  EXPECT_NEAR((left / nl) / (right / nr), 4.0, 0.05);
}

TEST(AdaptiveAllocation, ANoiseFreeRegionGetsOnlyTheFloor) {
  const int w = 40, h = 20;
  AdaptiveInputs in = uniform_inputs(w, h, 16, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = w / 2; x < w; ++x) in.pixel_error[size_t(y) * w + x] = 1e-3 * (1 + (x * 7 + y * 3) % 5);
  AdaptiveOptions options;
  const std::vector<uint32_t> k = allocate_wave_samples(in, 32, 128, options);
  // The floor after the wave: a quarter of the mean, 12, under min_spp: 16
  // samples, which the pixels already have.
  const int reach = options.filter_radius + options.dilate_radius;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2 - reach; ++x) EXPECT_EQ(k[size_t(y) * w + x], 0u) << x << "," << y;
  for (int y = 0; y < h; ++y)
    for (int x = w / 2; x < w; ++x) EXPECT_GT(k[size_t(y) * w + x], 32u) << x << "," << y;
}

// A stiff case: one pixel's estimate 10^12 times its neighbours' (a
// firefly at a few spp). Pixels whose filter never reaches it keep their
// weights to 1e-9: its value must not round the sums elsewhere (a
// summed-area table would: 10^12 x 2^-52 is about the small values' size).
TEST(AdaptiveAllocation, AHugeEstimateChangesOnlyItsNeighbourhood) {
  const int w = 32, h = 24;
  AdaptiveInputs calm = uniform_inputs(w, h, 16, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) calm.pixel_error[size_t(y) * w + x] = 1e-4 * (1 + (x * 5 + y * 3) % 7);
  AdaptiveInputs firefly = calm;
  firefly.pixel_error[size_t(2) * w + 2] = 1e8;
  AdaptiveOptions options;
  const std::vector<double> a = neyman_weights(calm, options), b = neyman_weights(firefly, options);
  // Each weight is sqrt(filtered v) plus 1e-9 of the largest (so none is 0).
  auto least = [](const std::vector<double>& weights) {
    return 1e-9 * *std::max_element(weights.begin(), weights.end()) / (1.0 + 1e-9);
  };
  const double la = least(a), lb = least(b);
  const int reach = options.filter_radius + options.dilate_radius;
  int far = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * w + x;
      if (x == 2 && y == 2) {  // the firefly's own pixel: its own estimate is left out of its weight
        // (subtracted from its neighbours' box sums: exact to 1e8 x 2^-52)
        EXPECT_NEAR((b[p] - lb) / (a[p] - la), 1.0, 1e-6);
        continue;
      }
      if (std::max(std::abs(x - 2), std::abs(y - 2)) <= reach) {
        EXPECT_GT(b[p] - lb, 1e3 * (a[p] - la)) << x << "," << y;  // within reach: it counts
        continue;
      }
      ++far;
      EXPECT_NEAR((b[p] - lb) / (a[p] - la), 1.0, 1e-9) << x << "," << y;
    }
  EXPECT_GT(far, w * h / 2);
}

TEST(AdaptiveAllocation, CostlierPixelsGetFewerSamplesAsTheSquareRootOfTheirCost) {
  // Equal time: the same per-sample variance everywhere, the left half's
  // samples costing 4 rays, the right half's 1. Neyman's n ~ sqrt(v / c)
  // gives the left half half the right's total, away from the border
  // (where the box filters mix the two).
  const int w = 32, h = 16;
  AdaptiveInputs in = uniform_inputs(w, h, 16, 0.01);
  in.rays.assign(size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) in.rays[size_t(y) * w + x] = (x < w / 2 ? 4u : 1u) * 16u;
  AdaptiveOptions options;
  options.uniform_share = 0.0;
  const std::vector<uint32_t> k = allocate_wave_samples(in, 48, 1u << 16, options);
  EXPECT_EQ(sum(k), uint64_t(48) * w * h);
  for (int y = 0; y < h; ++y) {
    const double left = 16.0 + k[size_t(y) * w + 3], right = 16.0 + k[size_t(y) * w + w - 4];
    EXPECT_NEAR(left / right, 0.5, 0.02) << y;
  }
  // Without ray counts every sample costs alike: the totals are even.
  in.rays.clear();
  const std::vector<uint32_t> even = allocate_wave_samples(in, 48, 1u << 16, options);
  EXPECT_EQ(*std::min_element(even.begin(), even.end()), *std::max_element(even.begin(), even.end()));
}

// place_wave_samples written the plain way, as it first was: the multiplier
// (or the lowered floor) by bisection down to adjacent doubles from a
// power-of-two bracket, the remainder by a full sort of the fractions. The
// renderer finds the same multiplier by false position and the same pixels
// by selection (to keep a GPU from waiting on the host between waves);
// the counts, and so the render's bits, must not change.
std::vector<uint32_t> place_by_bisection(const std::vector<double>& weight, const std::vector<uint32_t>& spp,
                                         int passes, uint32_t cap, const AdaptiveOptions& options) {
  const size_t pixels = spp.size();
  const uint64_t budget = uint64_t(passes) * pixels;
  const double total = double(std::accumulate(spp.begin(), spp.end(), uint64_t(0)));
  const double floor_total = std::max(double(options.min_spp), std::ceil(options.uniform_share * (total + double(budget)) / double(pixels)));
  std::vector<double> k(pixels);
  const auto place = [&](double lambda, double floor_at) {
    double sum = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
      k[p] = std::clamp(std::max(floor_at, lambda * weight[p]) - double(spp[p]), 0.0, double(cap));
      sum += k[p];
    }
    return sum;
  };
  const auto bisect = [](auto f, double lo, double hi, double target) {
    for (int i = 0; i < 200 && lo < hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (f(mid) >= target ? hi : lo) = mid;
    }
    return hi;
  };
  const double wanted = double(budget);
  if (place(0.0, floor_total) >= wanted) {
    place(0.0, bisect([&](double f) { return place(0.0, f); }, 0.0, floor_total, wanted));
  } else {
    double hi = 1.0;
    while (place(hi, floor_total) < wanted) hi *= 2.0;
    place(bisect([&](double lambda) { return place(lambda, floor_total); }, 0.0, hi, wanted), floor_total);
  }
  std::vector<uint32_t> whole(pixels);
  uint64_t placed = 0;
  for (size_t p = 0; p < pixels; ++p) placed += whole[p] = uint32_t(std::floor(k[p]));
  std::vector<uint32_t> order(pixels);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const double fa = k[a] - std::floor(k[a]), fb = k[b] - std::floor(k[b]);
    return fa != fb ? fa > fb : a < b;
  });
  for (uint64_t i = 0; placed + i < budget && i < pixels; ++i) ++whole[order[i]];
  return whole;
}

TEST(AdaptiveAllocation, PlacesTheSameCountsAsBisectionAndAFullSort) {
  std::mt19937 rng(11);
  std::lognormal_distribution<double> error(-9.0, 2.5);
  std::uniform_int_distribution<uint32_t> behind(16, 40);
  int checked = 0;
  for (int side : {1, 7, 64, 181}) {
    for (int trial = 0; trial < 6; ++trial) {
      AdaptiveInputs in = uniform_inputs(side, side, 16, 0.0);
      for (double& e : in.pixel_error) e = trial == 5 ? 0.0 : error(rng);   // trial 5: every weight alike
      if (trial >= 3)
        for (uint32_t& n : in.spp) n = behind(rng);  // uneven counts: the floor alone may take the wave
      if (trial == 4) {  // uneven costs
        in.rays.resize(in.spp.size());
        for (size_t p = 0; p < in.rays.size(); ++p) in.rays[p] = uint64_t(in.spp[p]) * (1 + p % 7);
      }
      const std::vector<double> weight = neyman_weights(in, AdaptiveOptions{});
      for (int passes : {1, 2, 16, 48}) {
        for (uint32_t cap : {uint32_t(passes), 64u, 1u << 16}) {
          if (cap < uint32_t(passes)) continue;
          EXPECT_EQ(place_wave_samples(weight, in.spp, passes, cap, AdaptiveOptions{}),
                    place_by_bisection(weight, in.spp, passes, cap, AdaptiveOptions{}))
              << side << "x" << side << ", trial " << trial << ", " << passes << " passes, cap " << cap;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(AdaptiveAllocation, InconsistentInputsAreErrors) {
  AdaptiveInputs in = uniform_inputs(4, 4, 16, 1e-3);
  in.spp.pop_back();
  EXPECT_TRUE(test::Contains(test::error_of([&] { allocate_wave_samples(in, 4, 128, AdaptiveOptions{}); }),
                             {"16 errors, 15 counts and 0 ray counts for 4x4 pixels"}));
  in = uniform_inputs(4, 4, 16, 1e-3);
  in.rays.assign(3, 16);
  EXPECT_TRUE(test::Contains(test::error_of([&] { allocate_wave_samples(in, 4, 128, AdaptiveOptions{}); }),
                             {"16 errors, 16 counts and 3 ray counts for 4x4 pixels"}));
  in = uniform_inputs(4, 4, 16, 1e-3);
  EXPECT_TRUE(test::Contains(test::error_of([&] { allocate_wave_samples(in, 200, 128, AdaptiveOptions{}); }),
                             {"a wave of 200 passes"}));
}

// Left half: the black background, exactly zero in every sample. Right half:
// a diffuse wall lit by a small area light (noisy).
const char* kHalfNoisy = R"({"nbounces": 4, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 48, "height": 32, "position": [0, 0, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 50},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [{"type": "arealight", "position": [-0.2, 1.5, -1.0], "u": [0.4, 0, 0], "v": [0, 0, 0.4],
                      "intensity": [20, 20, 20]}],
    "shapes": [{"type": "rectangle", "v0": [0, -10, 1], "v1": [0, 10, 1], "v2": [10, 10, 1], "v3": [10, -10, 1],
                "material": {"kd": 0.8, "ks": 0.0, "diffusecolor": [0.7, 0.7, 0.7]}},
               {"type": "rectangle", "v0": [-10, -10, 1], "v1": [-10, 10, 1], "v2": [0, 10, 1], "v3": [0, -10, 1],
                "material": {"kd": 0.0, "ks": 0.0, "diffusecolor": [0, 0, 0]}}]}})";

TEST(AdaptiveSampling, TheNoiseFreeHalfGetsOnlyTheMinimum) {
  // On Oclgrind 24x16 pixels and 24 spp (16 uniform, then one uneven wave).
  const int spp = int(test::sized(64, 24));
  std::string scene = kHalfNoisy;
  if (test::on_simulator()) {
    const std::string full = "\"width\": 48, \"height\": 32";
    scene.replace(scene.find(full), full.size(), "\"width\": 24, \"height\": 16");
  }
  PathRenderOptions o;
  o.adaptive = true;
  const PathRender r = render_path(write_scene("half.json", scene), spp, o);
  const int w = r.image.width, h = r.image.height;
  // Noise-free: every channel of the pixel and of its 7x7 neighbourhood
  // exactly zero (beyond the filter and dilation's reach of the wall).
  auto black = [&](int x, int y) {
    for (int yy = std::max(0, y - 3); yy <= std::min(h - 1, y + 3); ++yy)
      for (int xx = std::max(0, x - 3); xx <= std::min(w - 1, x + 3); ++xx)
        for (int c = 0; c < 3; ++c)
          if (r.image.at(xx, yy)[c] != 0.0f) return false;
    return true;
  };
  const uint32_t minimum = AdaptiveOptions{}.min_spp;
  int free_pixels = 0, lit_pixels = 0;
  double lit_spp = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t n = r.spp[size_t(y) * w + x];
      if (black(x, y)) {
        ++free_pixels;
        EXPECT_EQ(n, minimum) << x << "," << y;
      } else if (r.image.at(x, y)[0] > 0.0f) {
        ++lit_pixels;
        lit_spp += n;
      }
    }
  ASSERT_GT(free_pixels, w * h / 4);
  ASSERT_GT(lit_pixels, w * h / 4);
  EXPECT_EQ(sum(r.spp), uint64_t(spp) * w * h);  // the mean stays the asked spp
  // The cost it weighs: every ray the render traced, counted for its pixel.
  const uint64_t traced = std::accumulate(r.pixel_rays.begin(), r.pixel_rays.end(), uint64_t(0));
  EXPECT_EQ(traced, r.stats.camera_rays + r.stats.secondary_rays + r.stats.shadow_rays);
  for (size_t p = 0; p < r.spp.size(); ++p) ASSERT_GE(r.pixel_rays[p], r.spp[p]) << p;  // a camera ray each
  EXPECT_GT(lit_spp / lit_pixels, double(spp));  // the samples the black half did not take (1.75x at 64 spp)
}

// A glass sphere focuses a small light onto the floor (path tracing alone:
// the caustic is a rare, heavy-tailed path), next to flat diffuse regions.
const char* kCaustic = R"({"nbounces": 8, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 48, "height": 36, "position": [0, 3.2, 7.5], "lookAt": [0, 1.0, 0],
             "upVector": [0, 1, 0], "fov": 42},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [{"type": "arealight", "position": [-0.4, 5.0, 0.8], "u": [0.4, 0, 0], "v": [0, 0, 0.4],
                      "intensity": [120, 115, 105]}],
    "shapes": [{"type": "rectangle", "v0": [-6, 0, -4], "v1": [-6, 0, 6], "v2": [6, 0, 6], "v3": [6, 0, -4],
                "material": {"kd": 0.8, "ks": 0.0, "diffusecolor": [0.75, 0.7, 0.65]}},
               {"type": "rectangle", "v0": [-6, 0, -4], "v1": [6, 0, -4], "v2": [6, 6, -4], "v3": [-6, 6, -4],
                "material": {"kd": 0.8, "ks": 0.0, "diffusecolor": [0.75, 0.7, 0.65]}},
               {"type": "sphere", "center": [-0.9, 1.1, 0.6], "radius": 1.0,
                "material": {"isrefractive": true, "refractiveindex": 1.5, "diffusecolor": [1, 1, 1],
                             "specularcolor": [1, 1, 1]}}]}})";

PathRender render_caustic(int spp, bool adaptive, uint32_t seed, size_t local_size = 64, size_t slots = 0,
                          const char* size = nullptr) {
  std::string scene = kCaustic;
  const std::string full_size = "\"width\": 48, \"height\": 36";
  if (size) scene.replace(scene.find(full_size), full_size.size(), size);
  PathRenderOptions o;
  o.adaptive = adaptive;
  o.seed = seed;
  o.caustics = CausticsMode::Off;
  o.local_size = local_size;
  o.path_slots = slots;
  return render_path(write_scene("caustic.json", scene), spp, o);
}

double region_mean(const ImageF& image, const std::vector<char>& in_region) {
  double s = 0.0;
  int n = 0;
  for (size_t p = 0; p < in_region.size(); ++p)
    if (in_region[p]) {
      s += double(image.rgb[3 * p]) + image.rgb[3 * p + 1] + image.rgb[3 * p + 2];
      ++n;
    }
  return s / (3.0 * std::max(1, n));
}

TEST(AdaptiveSampling, TheMeanOverSeedsMatchesALongUniformRender) {
  if (test::on_simulator()) GTEST_SKIP() << "thousands of samples a pixel: too slow on a simulator";
  const int spp = 64, seeds = 48;
  const PathRender reference = render_caustic(2048, false, 1000);
  std::vector<PathRender> runs;
  for (int s = 0; s < seeds; ++s) runs.push_back(render_caustic(spp, true, uint32_t(s)));
  const size_t pixels = reference.image.pixel_count();
  // Regions of the first run's allocation: pixels it gave half the mean or
  // less (stopped early), pixels it gave 4x the mean or more (the caustic),
  // and the whole image.
  std::vector<char> stopped(pixels), piled(pixels), all(pixels, 1);
  for (size_t p = 0; p < pixels; ++p) {
    stopped[p] = 2u * runs[0].spp[p] <= uint32_t(spp);
    piled[p] = runs[0].spp[p] >= 4u * spp;
  }
  struct Region {
    const char* name;
    const std::vector<char>& pixels;
  };
  for (const Region& region : {Region{"whole image", all}, Region{"given half the mean or less", stopped},
                               Region{"given 4x the mean or more", piled}}) {
    const int count = int(std::count(region.pixels.begin(), region.pixels.end(), 1));
    ASSERT_GE(count, 20) << region.name;
    // The reference's standard error from its half buffer (uniform, 2048 =
    // 2^11: the halves are equal), the adaptive mean's from the seeds.
    double ref_var = 0.0;
    for (size_t p = 0; p < pixels; ++p)
      if (region.pixels[p])
        for (int c = 0; c < 3; ++c) {
          const double d = double(reference.image.rgb[3 * p + c]) - reference.half.rgb[3 * p + c];
          ref_var += d * d;
        }
    const double ref = region_mean(reference.image, region.pixels), ref_se = std::sqrt(ref_var) / (3.0 * count);
    std::vector<double> means;
    for (const PathRender& r : runs) means.push_back(region_mean(r.image, region.pixels));
    const double mean = std::accumulate(means.begin(), means.end(), 0.0) / seeds;
    double var = 0.0;
    for (double m : means) var += (m - mean) * (m - mean);
    const double se = std::sqrt(var / (seeds - 1) / seeds), combined = std::hypot(se, ref_se);
    std::printf("[measure] %s (%d pixels): adaptive mean over %d seeds %.5f +- %.5f, reference %.5f +- %.5f, "
                "difference %.2f standard errors\n",
                region.name, count, seeds, mean, se, ref, ref_se, (mean - ref) / combined);
    EXPECT_LE(std::abs(mean - ref), 3.5 * combined) << region.name;
    // The check can see a bias: over the whole image 3.5 standard errors
    // are under 2% of its light (an allocation that weighed each pixel's
    // own estimate measured -1.9%, 5.2 standard errors), in the regions
    // under 10%.
    EXPECT_LT(3.5 * combined, (count == int(pixels) ? 0.02 : 0.10) * ref) << region.name;
  }
}

// On Oclgrind (in CI) a 16x12 image, 16 uniform and 8 adaptive samples:
// the uneven waves' pixel list and binary search, and the film's per-pixel
// accumulation, run there too.
TEST(AdaptiveSampling, TheSameSeedGivesTheSameBitsForAnyWorkGroupSizeOrSlotCount) {
  const int spp = int(test::sized(48, 24));
  const char* size = test::on_simulator() ? "\"width\": 16, \"height\": 12" : nullptr;
  const PathRender a = render_caustic(spp, true, 5, 64, 0, size);
  const PathRender b = render_caustic(spp, true, 5, 32, 4096, size);
  const PathRender c = render_caustic(spp, true, 5, 128, 1000, size);
  EXPECT_EQ(a.spp, b.spp);
  EXPECT_EQ(a.spp, c.spp);
  EXPECT_TRUE(a.image.rgb == b.image.rgb);
  EXPECT_TRUE(a.image.rgb == c.image.rgb);
  // and the allocation really was uneven
  EXPECT_NE(*std::min_element(a.spp.begin(), a.spp.end()), *std::max_element(a.spp.begin(), a.spp.end()));
}

}  // namespace
}  // namespace caustica
