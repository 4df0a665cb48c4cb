// The render core: record layouts agree between host and device, kernel
// arguments are bound under the kernel's own names, the film keeps the HDR
// range and counts what it drops, passes accumulate deterministically and
// survive queue-overflow retries, one shade_surface_phong step on a
// hand-built hit, and the mode is a render-time choice.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>

#include "host/app/session.h"
#include "host/bench/host_trace.h"
#include "host/error.h"
#include "host/render/device_scene.h"
#include "host/render/adaptive_sampling.h"
#include "host/render/film.h"
#include "host/render/pixel_share.h"
#include "host/render/kernel_args.h"
#include "host/lights/light_table.h"
#include "host/render/renderer.h"
#include "host/scene/load_scene.h"
#include "kernels/shared/photon.h"
#include "lib/film_sums.h"
#include "kernels/shared/records.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

// ------------------------------------------------------------------ layout

// Every size and offset the two sides must agree on, written once
// (tests/kernels/record_layout.h): the host evaluates the list here, and
// tests/kernels/record_layout.cl evaluates it on the device.
#include "tests/kernels/record_layout.h"

#define CAUSTICA_STR(...) #__VA_ARGS__
#define HOST_VALUE(e) uint32_t(e),

TEST(RecordLayout, DeviceAgreesWithHost) {
  const std::vector<uint32_t> host = {LAYOUT_EXPRESSIONS(HOST_VALUE)};
  Runtime& rt = test::runtime();
  const BuiltProgram built = test::build_test_kernel("record_layout.cl", "");
  cl::Kernel kernel(built.program, "layout");
  cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, host.size() * sizeof(cl_uint));
  kernel.setArg(0, out);
  rt.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
  std::vector<uint32_t> device(host.size());
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, device.size() * sizeof(cl_uint), device.data());
  const char* names[] = {LAYOUT_EXPRESSIONS(CAUSTICA_STR)};
  for (size_t i = 0; i < host.size(); ++i) EXPECT_EQ(device[i], host[i]) << names[i];
  // The SoA queues allocate one element of each field's type per slot.
  size_t path_bytes = 0;
  for (const RecordField& f : path_record_layout().fields) path_bytes += f.bytes;
  // Every field, no gap between them and no tail padding.
  EXPECT_EQ(path_bytes, offsetof(PathRecord, light_normal) + sizeof(cl_uint));
  EXPECT_EQ(path_bytes, sizeof(PathRecord));
  EXPECT_EQ(path_bytes, 80u);
  EXPECT_EQ(path_record_layout().fields.size(), 11u);
  size_t photon_bytes = 0;
  for (const RecordField& f : photon_record_layout().fields) photon_bytes += f.bytes;
  EXPECT_EQ(photon_bytes, sizeof(PhotonRecord));
  EXPECT_EQ(photon_bytes, 64u);
  EXPECT_EQ(photon_record_layout().fields.size(), 7u);
  EXPECT_EQ(shadow_record_layout().fields.size(), 5u);
}

// ------------------------------------------------------------------ binding

TEST(KernelArgs, BindingIsCheckedAgainstTheKernelsNames) {
  Runtime& rt = test::runtime();
  const BuiltProgram built = rt.build_file("integrator_binary.cl", " -DHAS_SPHERES");
  const DeviceQueue rays(rt.context(), path_record_layout(), 16);
  const CameraGPU camera{};
  {
    StageKernel generate(built.program, "generate_camera_rays");
    KernelArgs(generate).arg("camera", camera).queue("out", rays).arg("next_count", rays.count()).finish();  // as the integrators bind it
    EXPECT_TRUE(generate.binding_checked);
  }
  if (kernel_arg_names(StageKernel(built.program, "generate_camera_rays").kernel).empty())
    GTEST_SKIP() << "this device does not report kernel argument names";
  StageKernel wrong_prefix(built.program, "generate_camera_rays");
  try {
    KernelArgs(wrong_prefix).arg("camera", camera).queue("in", rays).arg("next_count", rays.count()).finish();
    ADD_FAILURE() << "a binding under other names was accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(test::Contains(e.what(), {"generate_camera_rays", "argument 1", "\"out_count\"", "\"in_count\""}));
  }
  StageKernel too_few(built.program, "generate_camera_rays");
  try {
    KernelArgs(too_few).arg("camera", camera).finish();
    ADD_FAILURE() << "a binding with too few arguments was accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(test::Contains(e.what(), {"generate_camera_rays", "declares 14 arguments", "binds 1"}));
  }
}

// ------------------------------------------------------------------ film

// film_add from a list of contributions, plus the pass accumulation, in one
// program (tests/kernels/render_core_film.cl): the Film class drives it as
// the integrators do.
struct FilmRig {
  Runtime& rt = test::runtime();
  BuiltProgram built = test::build_test_kernel("render_core_film.cl", "", rt);
  Film film;
  StageKernel add{built.program, "add_contributions"};
  StageLauncher launcher{rt, 64};

  explicit FilmRig(const FilmOptions& options) : film(rt, built.program, options) {}

  void add_pass(const std::vector<cs_float4>& values, const std::vector<uint32_t>& pixels, size_t local = 64) {
    const cl::Buffer v = upload_buffer(rt.context(), values), p = upload_buffer(rt.context(), pixels);
    KernelArgs args(add);
    film.bind(args).arg("values", v).arg("pixels", p).arg("count", cl_uint(values.size())).finish();
    rt.queue().enqueueNDRangeKernel(add.kernel, cl::NullRange, cl::NDRange(round_up(values.size(), local)),
                                    cl::NDRange(local));
    rt.queue().finish();
  }
};

FilmOptions film_options(int width, int height, bool half = false) {
  FilmOptions o;
  o.width = width;
  o.height = height;
  o.half_buffer = half;
  return o;
}

// The half buffer holds passes [P, N), P the largest power of two below N:
// pass k adds k + 1 to pixel 0, so the half's mean is known exactly.
TEST(Film, HalfBufferHoldsThePassesSinceTheLatestPowerOfTwo) {
  FilmRig rig(film_options(2, 1, true));
  for (int n = 1; n <= 19; ++n) {
    rig.add_pass({{{float(n), 0.0f, 0.0f, 0.0f}}}, {0u});
    rig.film.accumulate_pass(rig.launcher);
    if (n < 2) continue;
    int first = 1;
    while (2 * first < n) first *= 2;
    ASSERT_EQ(rig.film.half_passes(), n - first) << n << " passes";
    double sum = 0.0;
    for (int k = first + 1; k <= n; ++k) sum += k;
    EXPECT_FLOAT_EQ(rig.film.half_mean().rgb[0], float(sum / (n - first))) << n << " passes";
    EXPECT_FLOAT_EQ(rig.film.mean().rgb[0], float(n + 1) / 2.0f) << n << " passes";
  }
}

// Waves (path mode): passes [N, N + k) added into one pass in progress and
// accumulated at once. Waves grow 1, 1, 2, 4, ... along the half buffer's
// restarts and give the sums and halves that pass-by-pass accumulation
// gives; a wave across a restart, or past kMostWavePasses, is refused.
TEST(Film, WavesOfPassesAccumulateLikeTheirPasses) {
  EXPECT_EQ(Film::most_passes_from(0, 100), 1);
  EXPECT_EQ(Film::most_passes_from(1, 100), 1);
  EXPECT_EQ(Film::most_passes_from(2, 100), 2);
  EXPECT_EQ(Film::most_passes_from(3, 100), 1);
  EXPECT_EQ(Film::most_passes_from(4, 100), 4);
  EXPECT_EQ(Film::most_passes_from(64, 100), 64);
  EXPECT_EQ(Film::most_passes_from(256, 1000), Film::kMostWavePasses);
  EXPECT_EQ(Film::most_passes_from(384, 1000), Film::kMostWavePasses);
  EXPECT_EQ(Film::most_passes_from(8, 3), 3);
  FilmRig waves(film_options(2, 1, true)), single(film_options(2, 1, true));
  for (int n = 0; n < 40;) {
    const int k = Film::most_passes_from(n, 100);
    for (int p = n; p < n + k; ++p) {  // pass p adds p + 1 to pixel 0
      waves.add_pass({{float(p + 1), 0.0f, 0.0f, 0.0f}}, {0u});
      single.add_pass({{float(p + 1), 0.0f, 0.0f, 0.0f}}, {0u});
      single.film.accumulate_pass(single.launcher);
    }
    waves.film.accumulate_pass(waves.launcher, nullptr, k);
    n += k;
    ASSERT_EQ(waves.film.passes(), n);
    EXPECT_EQ(waves.film.mean().rgb[0], single.film.mean().rgb[0]) << n << " passes";  // integers: exact
    if (n >= 2) {
      ASSERT_EQ(waves.film.half_passes(), single.film.half_passes());
      EXPECT_EQ(waves.film.half_mean().rgb[0], single.film.half_mean().rgb[0]) << n << " passes";
    }
  }
  FilmRig crossing(film_options(2, 1, true));
  crossing.film.accumulate_pass(crossing.launcher);
  crossing.film.accumulate_pass(crossing.launcher);
  crossing.film.accumulate_pass(crossing.launcher);  // 3 passes: the next restart is at 4
  EXPECT_THROW(crossing.film.accumulate_pass(crossing.launcher, nullptr, 2), Error);
  EXPECT_THROW(crossing.film.accumulate_pass(crossing.launcher, nullptr, Film::kMostWavePasses + 1), Error);
  EXPECT_THROW(crossing.film.accumulate_pass(crossing.launcher, nullptr, 0), Error);
}

// The accumulated sums are integers (issue 23: states from several
// processes add to the bits of one): passes of values that are not whole
// numbers give the same mean and half bits whether they came one by one or
// in waves (float sums, as before, rounded differently).
TEST(Film, SumsDoNotDependOnTheWavesThePassesCameIn) {
  FilmRig waves(film_options(2, 1, true)), single(film_options(2, 1, true));
  auto value = [](int p) { return float(0.1 * (p + 1) + 1.0 / 3.0); };
  int n = 0;
  while (n < 100) {
    const int k = Film::most_passes_from(n, 100);
    for (int p = n; p < n + k; ++p) {
      waves.add_pass({{value(p), 0.0f, 0.0f, 0.0f}}, {0u});
      single.add_pass({{value(p), 0.0f, 0.0f, 0.0f}}, {0u});
      single.film.accumulate_pass(single.launcher);
    }
    waves.film.accumulate_pass(waves.launcher, nullptr, k);
    n += k;
    ASSERT_EQ(waves.film.mean().rgb[0], single.film.mean().rgb[0]) << n << " passes";
    if (n >= 2) ASSERT_EQ(waves.film.half_mean().rgb[0], single.film.half_mean().rgb[0]) << n << " passes";
  }
  double exact = 0.0;
  for (int p = 0; p < n; ++p) exact += value(p);
  EXPECT_NEAR(single.film.mean().rgb[0], exact / n, 1e-6 * exact / n);
}

// A 128-bit sum becomes the nearest float, ties to even, in one rounding
// (kernels/lib/film_sums.h, on the host; the device's is the same code, and
// the tests above read every film through it).
TEST(Film, WideSumsRoundOnceToTheNearestFloat) {
  // In units of the fixed point (the scale back is a power of two: exact).
  auto sum128_to_float = [](uint64_t low, uint64_t high) {
    return std::ldexp(film_sum_to_float(low, high), FILM_FRACTION_BITS);
  };
  const float two64 = std::ldexp(1.0f, 64);
  EXPECT_EQ(sum128_to_float(12345, 0), 12345.0f);
  EXPECT_EQ(sum128_to_float(~uint64_t(0), 0), two64);  // 2^64 - 1 rounds up
  EXPECT_EQ(sum128_to_float(0, 1), two64);
  // Floats near 2^64 are 2^41 apart: 2^64 + 2^40 is a tie (to even, 2^64);
  // one more and it rounds up, which only the bits below the top 64 tell.
  EXPECT_EQ(sum128_to_float(uint64_t(1) << 40, 1), two64);
  EXPECT_EQ(sum128_to_float((uint64_t(1) << 40) + 1, 1), two64 + std::ldexp(1.0f, 41));
  EXPECT_EQ(sum128_to_float(0, uint64_t(1) << 63), std::ldexp(1.0f, 127));
  EXPECT_EQ(sum128_to_float(1, uint64_t(1) << 63), std::ldexp(1.0f, 127));
}

// Uneven waves (adaptive sampling): each pixel counts its own samples. A
// pixel's half restarts at n, the wave's first sample, whenever the wave's
// samples [n, n + k) hold a power of two (at it, for waves that start
// there). Sample i of pixel p adds i + 1 + 100 p, so means and halves are
// known exactly; plans that do not add up, exceed the cap or disagree with
// the accumulated wave are refused.
TEST(Film, UnevenWavesKeepEveryPixelsOwnCountAndHalf) {
  FilmRig rig(film_options(3, 1, true));
  const std::vector<std::vector<uint32_t>> waves = {{1, 1, 1}, {1, 1, 1}, {2, 2, 2}, {1, 5, 0},
                                                    {3, 0, 3}, {0, 6, 0}, {2, 2, 2}, {9, 0, 0}};
  std::vector<uint32_t> n(3, 0), half_start(3, 0);
  for (const auto& k : waves) {
    const int passes = int((k[0] + k[1] + k[2]) / 3);
    if (k[0] == k[1] && k[1] == k[2])
      rig.film.plan_wave(passes);
    else
      rig.film.plan_wave(passes, k);
    std::vector<cs_float4> values;
    std::vector<uint32_t> pixels;
    for (uint32_t p = 0; p < 3; ++p) {
      float wave_sum = 0.0f;
      bool restarts = false;
      for (uint32_t i = n[p]; i < n[p] + k[p]; ++i) {
        wave_sum += float(i + 1 + 100 * p);
        restarts = restarts || (n[p] > 0 && (i & (i - 1)) == 0);  // sample i is a power of two
      }
      if (restarts) half_start[p] = n[p];
      n[p] += k[p];
      if (k[p] > 0) {
        values.push_back({{wave_sum, 0.0f, 0.0f, 0.0f}});
        pixels.push_back(p);
      }
    }
    rig.add_pass(values, pixels);
    rig.film.accumulate_pass(rig.launcher, nullptr, passes);
    ASSERT_EQ(rig.film.pixel_spp(), n);
    const ImageF mean = rig.film.mean();
    const std::vector<uint32_t> h = rig.film.half_counts();
    for (uint32_t p = 0; p < 3; ++p) {
      EXPECT_FLOAT_EQ(mean.rgb[3 * p], float(n[p] + 1) / 2.0f + 100.0f * p) << "pixel " << p;
      EXPECT_EQ(h[p], half_start[p] > 0 ? n[p] - half_start[p] : 0u) << "pixel " << p;
      if (n[p] >= 2 && h[p] > 0)  // mean of samples [half_start, n): their indices + 1 average (start + n + 1) / 2
        EXPECT_FLOAT_EQ(rig.film.half_mean().rgb[3 * p], float(half_start[p] + n[p] + 1) / 2.0f + 100.0f * p)
            << "pixel " << p;
    }
  }
  EXPECT_EQ(rig.film.passes(), 15);
  EXPECT_FALSE(rig.film.uniform());
  EXPECT_TRUE(test::Contains(test::error_of([&] { rig.film.plan_wave(2, {1, 1, 1}); }),
                             {"a wave allocation of 3 samples, not 2 passes of 3 pixels"}));
  EXPECT_TRUE(test::Contains(test::error_of([&] { rig.film.plan_wave(1, {1, 1}); }), {"2 pixels for 3"}));
  // The cap: 2^16 samples a pixel in one wave (what the pass's 128 bits fit).
  FilmRig wide(film_options(1024, 1, true));
  std::vector<uint32_t> crowded(1024, 0u);
  crowded[0] = 65537;
  crowded[1] = 128 * 1024 - 65537;
  EXPECT_TRUE(test::Contains(test::error_of([&] { wide.film.plan_wave(128, crowded); }),
                             {"a pixel given 65537 samples in one wave (at most 65536)"}));
  rig.film.plan_wave(2, {3, 3, 0});
  EXPECT_TRUE(test::Contains(test::error_of([&] { rig.film.accumulate_pass(rig.launcher, nullptr, 1); }),
                             {"a wave of 1 passes accumulated, 2 planned"}));
}

// One process as a group of one (every collective an identity): what a
// film shared among processes computes from its summed sums must be, for a
// group of one, exactly what it computes alone.
class GroupOfOne final : public PixelShare {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::string gather_bytes_to_all(const std::string& mine) override { return mine; }
  std::vector<std::string> gather_bytes_to_root(const std::string& mine) override { return {mine}; }
  void sum_to_all(std::vector<uint64_t>&) override {}
  void sum128_to_all(std::vector<uint64_t>&) override {}
  std::vector<uint64_t> sum_scatter(const std::vector<uint64_t>& v, const std::vector<size_t>&) override { return v; }
  std::vector<uint64_t> sum128_scatter(const std::vector<uint64_t>& v, const std::vector<size_t>&) override {
    return v;
  }
  int broadcast(int value) override { return value; }
};

// Film::summed_means and summed_band (the host's conversion of the summed
// sums, the band taken on the device in 64-bit words or, with a sum past
// 2^64 in fixed point, in 128) give mean() and half_mean()'s bits, and the
// adaptive sampler's weights from them are its weights from the film alone.
TEST(Film, SummedMeansAndBandsOfAGroupOfOneAreTheFilmsOwn) {
  for (const float big : {0.0f, 3.0e6f}) {  // 3e6 x 2^44 > 2^64: the 128-bit path
    SCOPED_TRACE(big);
    FilmRig rig(film_options(5, 4, true));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> radiance(0.0f, 2.0f);
    for (int wave = 0; wave < 6; ++wave) {
      // Even waves, then uneven ones (some pixels without samples).
      std::vector<uint32_t> k(20, 1);
      if (wave >= 3) {
        for (size_t p = 0; p < k.size(); ++p) k[p] = (p % 3 == 0) ? 0 : (p % 3 == 1) ? 1 : 2;
        k[19] = 2;  // 20 samples: one pass's
      }
      if (wave >= 3)
        rig.film.plan_wave(1, k);
      else
        rig.film.plan_wave(1);
      std::vector<cs_float4> values;
      std::vector<uint32_t> pixels;
      for (uint32_t p = 0; p < 20; ++p)
        if (k[p] > 0) {
          values.push_back({{radiance(rng) * float(k[p]), radiance(rng), p == 7 ? big : radiance(rng), 0.0f}});
          pixels.push_back(p);
        }
      rig.add_pass(values, pixels);
      rig.film.accumulate_pass(rig.launcher, nullptr, 1);
    }
    ASSERT_FALSE(rig.film.uniform());
    GroupOfOne group;
    const ImageF mean = rig.film.mean(), half = rig.film.half_mean();
    const auto same = [](const ImageF& a, const ImageF& b) {
      return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
    };
    const Film::Means summed = rig.film.summed_means(group, true);
    EXPECT_TRUE(same(summed.mean, mean));
    EXPECT_TRUE(same(summed.half, half));
    const Film::Band band = rig.film.summed_band(group, true);
    EXPECT_EQ(band.first, 0u);
    EXPECT_EQ(band.end, 20u);
    EXPECT_TRUE(same(band.means.mean, mean));
    EXPECT_TRUE(same(band.means.half, half));
    EXPECT_EQ(band.rays, rig.film.pixel_rays());
    const AdaptiveOptions options;
    EXPECT_EQ(AdaptiveSampler::weights_of(rig.film, options, &group), AdaptiveSampler::weights_of(rig.film, options));
  }
}

TEST(Film, NonFiniteAndNegativeAreCountedAndDroppedHugeValuesClamped) {
  FilmRig rig(film_options(4, 1));
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float max = FILM_MAX_CONTRIBUTION;
  rig.add_pass({{nan, 0.5f, 0, 0}, {inf, -inf, 0.25f, 0}, {-1.0f, -0.0f, 2.0f, 0}, {3.0f * max, 1.0f, 0, 0}},
               {0, 1, 2, 3});
  rig.film.accumulate_pass(rig.launcher);
  const FilmCounts c = rig.film.counts();
  EXPECT_EQ(c.nonfinite, 3u);
  EXPECT_EQ(c.negative, 1u);  // -0 is zero, not negative
  EXPECT_EQ(c.clamped, 1u);
  const ImageF img = rig.film.mean();
  const float want[12] = {0, 0.5f, 0, 0, 0, 0.25f, 0, 0, 2.0f, max, 1.0f, 0};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(img.rgb[i], want[i]) << "value " << i;
}

// Issue 24: one fixed point for every render. A float from 2^-20 (1e-6)
// up comes back with every bit, 1e12 and 1e-6 in one image; below 2^-45 a
// contribution rounds to 0 and is counted, never silently.
TEST(Film, KeepsEveryBitFromAMillionthToATrillionInOneImage) {
  FilmRig rig(film_options(3, 1));
  rig.add_pass({{1e12f, 1e-6f, 1.0f, 0}, {12345.678f, 0.1f, 3e16f, 0}, {1e-14f, 0.0f, 0x1p-30f, 0}}, {0, 1, 2});
  rig.film.accumulate_pass(rig.launcher);
  const ImageF img = rig.film.mean();
  const FilmCounts c = rig.film.counts();
  EXPECT_EQ(c.changed(), 0u);
  EXPECT_EQ(c.underflow, 1u);  // 1e-14 < 2^-45
  const float want[9] = {1e12f, 1e-6f, 1.0f, 12345.678f, 0.1f, 3e16f, 0.0f, 0.0f, 0x1p-30f};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(img.rgb[i], want[i]) << "value " << i;
  // What the lost contribution could have held, against the image's light.
  const double share = rig.film.underflow_share(c.underflow);
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 1e-30);
}

// Into fixed point and back (kernels/lib/film_sums.h on the host, the
// device's code): exact from 2^-20 up, rounded to nearest (even) below.
TEST(Film, FloatsBecomeFixedPointExactlyOrRoundedToNearest) {
  auto round_trip = [](float v) {
    uint64_t low = 0, high = 0;
    film_fixed_from_float(v, &low, &high);
    return film_sum_to_float(low, high);
  };
  std::mt19937 rng(3);
  for (int i = 0; i < 200000; ++i) {
    // Every exponent from 2^-20 to 2^56, random mantissas.
    const uint32_t exponent = 127 - 20 + rng() % 77, bits = (exponent << 23) | (rng() & 0x7fffffu);
    float v;
    std::memcpy(&v, &bits, 4);
    ASSERT_EQ(round_trip(v), v) << v;
  }
  auto fixed = [](float v) {
    uint64_t low = 0, high = 0;
    film_fixed_from_float(v, &low, &high);
    EXPECT_EQ(high, 0u) << v;
    return low;
  };
  const float unit = std::ldexp(1.0f, -FILM_FRACTION_BITS);
  EXPECT_EQ(fixed(0.5f * unit), 0u);    // a tie: to even
  EXPECT_EQ(fixed(0.75f * unit), 1u);
  EXPECT_EQ(fixed(1.5f * unit), 2u);    // a tie: to even
  EXPECT_EQ(fixed(2.5f * unit), 2u);    // a tie: to even
  EXPECT_EQ(fixed(0x1.000002p-20f), (uint64_t(1) << 24) + 2u);  // its last bit is 2^-43
  EXPECT_EQ(fixed(1e-40f), 0u);         // subnormal
  uint64_t low = 0, high = 0;
  film_fixed_from_float(FILM_MAX_CONTRIBUTION, &low, &high);
  EXPECT_EQ(low, 0u);
  EXPECT_EQ(high, uint64_t(1) << (56 + FILM_FRACTION_BITS - 64));
  film_fixed_from_float(1.0f, &low, &high);
  EXPECT_EQ(low, uint64_t(1) << FILM_FRACTION_BITS);
  EXPECT_EQ(high, 0u);
  film_fixed_from_float(std::ldexp(1.0f, 20) * 1.5f, &low, &high);  // 1.5 * 2^64
  EXPECT_EQ(low, uint64_t(1) << 63);
  EXPECT_EQ(high, 1u);
}

// The pass's atomics carry from the low word into the high one: values
// near 2^20 are 2^64 in fixed point, so nearly every add wraps the low
// word. The sums are exact in any order and work-group size.
TEST(Film, CarriesIntoTheHighWordAddExactly) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(0x1p18f, 0x1p21f);
  std::vector<cs_float4> values(test::sized(4000, 400));
  std::vector<uint32_t> pixels(values.size());
  std::vector<unsigned __int128> exact(12, 0);
  for (size_t i = 0; i < values.size(); ++i) {
    values[i] = cs_float4{value(rng), value(rng), value(rng), 0};
    pixels[i] = uint32_t(rng() % 4);
    for (int c = 0; c < 3; ++c) {
      uint64_t low = 0, high = 0;
      film_fixed_from_float((&values[i].x)[c], &low, &high);
      exact[3 * pixels[i] + c] += (static_cast<unsigned __int128>(high) << 64) | low;
    }
  }
  for (size_t local : {1, 64}) {
    FilmRig rig(film_options(4, 1));
    rig.add_pass(values, pixels, local);
    rig.film.accumulate_pass(rig.launcher);
    const ImageF sums = rig.film.mean();  // one pass: the sums
    for (int i = 0; i < 12; ++i)
      ASSERT_EQ(sums.rgb[i], film_sum_to_float(uint64_t(exact[i]), uint64_t(exact[i] >> 64)))
          << "value " << i << ", work-group " << local;
  }
}

TEST(Film, AccumulationIsOrderIndependentAndPassesAverage) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(0.0f, 3.0f);
  // Cut on the simulator: 2000 splats, still ~170 colliding atomic adds per
  // pixel for the order-independence to be tested (18 films of 20000 take
  // 20 s there).
  std::vector<cs_float4> values(test::sized(20000, 2000));
  std::vector<uint32_t> pixels(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    values[i] = cs_float4{value(rng), value(rng), value(rng), 0};
    pixels[i] = uint32_t(rng() % 12);
  }
  std::vector<size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<cs_float4> shuffled_values;
  std::vector<uint32_t> shuffled_pixels;
  for (size_t i : order) shuffled_values.push_back(values[i]), shuffled_pixels.push_back(pixels[i]);

  ImageF first;
  for (size_t local : {1, 8, 64}) {
    for (int shuffled = 0; shuffled < 2; ++shuffled) {
      FilmRig rig(film_options(4, 3, true));
      for (int pass = 0; pass < 3; ++pass)
        rig.add_pass(shuffled ? shuffled_values : values, shuffled ? shuffled_pixels : pixels, local),
            rig.film.accumulate_pass(rig.launcher);
      const ImageF mean = rig.film.mean();
      EXPECT_EQ(rig.film.passes(), 3);
      // Three equal passes: their mean, and the half (pass 2 alone), equal one pass's sum.
      const ImageF half = rig.film.half_mean();
      for (size_t i = 0; i < mean.rgb.size(); ++i) EXPECT_NEAR(mean.rgb[i], half.rgb[i], 1e-6f * half.rgb[i]);
      if (first.rgb.empty()) {
        first = mean;
        continue;
      }
      EXPECT_EQ(0, std::memcmp(first.rgb.data(), mean.rgb.data(), first.rgb.size() * sizeof(float)))
          << "local size " << local << (shuffled ? ", shuffled" : "");
    }
  }
  // Against the exact sums in double.
  std::vector<double> exact(36, 0.0);
  for (size_t i = 0; i < values.size(); ++i) {
    exact[3 * pixels[i] + 0] += values[i].x;
    exact[3 * pixels[i] + 1] += values[i].y;
    exact[3 * pixels[i] + 2] += values[i].z;
  }
  for (size_t i = 0; i < exact.size(); ++i) EXPECT_NEAR(first.rgb[i], exact[i], 1e-5 * exact[i]) << i;
}

TEST(Film, ClearingAPassRangeKeepsFinishedPasses) {
  FilmRig rig(film_options(4, 1));
  rig.add_pass({{1, 1, 1, 0}, {1, 1, 1, 0}, {1, 1, 1, 0}, {1, 1, 1, 0}}, {0, 1, 2, 3});
  rig.film.accumulate_pass(rig.launcher);
  // Blue: 2^30, whose fixed point is in the pass's high words.
  rig.add_pass({{1, 1, 0x1p30f, 0}, {1, 1, 0x1p30f, 0}, {1, 1, 0x1p30f, 0}, {1, 1, 0x1p30f, 0}}, {0, 1, 2, 3});
  rig.film.clear_pass_range(1, 2);  // pixels 1 and 2 of the pass in progress
  rig.film.accumulate_pass(rig.launcher);
  const ImageF img = rig.film.mean();  // (1 + 1) / 2 and (1 + 0) / 2
  EXPECT_EQ(img.rgb[0], 1.0f);
  EXPECT_EQ(img.rgb[3], 0.5f);
  EXPECT_EQ(img.rgb[6], 0.5f);
  EXPECT_EQ(img.rgb[9], 1.0f);
  EXPECT_EQ(img.rgb[2], (1.0f + 0x1p30f) / 2.0f);
  EXPECT_EQ(img.rgb[5], 0.5f);
  EXPECT_EQ(img.rgb[8], 0.5f);
  EXPECT_EQ(img.rgb[11], (1.0f + 0x1p30f) / 2.0f);
}

// ------------------------------------------------------------------ one shade step

// A sphere of radius 1 at the origin, hit from above at (0, 1, 0); a point
// light straight above; a mirror share of 0.25; a second ray that misses.
// One shade_surface_phong step must add the ambient term and the weighted
// background to the film, fill the hit's shadow slot with the Blinn-Phong
// value and leave the miss's empty, and push one mirror child of weight 0.25.
TEST(ShadeSurfacePhong, OneStepOnAHandBuiltHit) {
  const nlohmann::json j = R"({"nbounces": 2, "rendermode": "phong",
    "camera": {"type": "pinhole", "width": 4, "height": 4, "position": [0, 3, -3], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 40, "exposure": 0},
    "scene": {"backgroundcolor": [0.1, 0.2, 0.3],
      "lightsources": [{"type": "pointlight", "position": [0, 5, 0], "intensity": [2, 2, 2]}],
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.0,
        "material": {"kd": 0.8, "ks": 0.5, "specularexponent": 10, "diffusecolor": [0.5, 0.25, 1.0],
                     "specularcolor": [1, 1, 1], "isreflective": true, "reflectivity": 0.25}}]}})"_json;
  const Scene scene = parse_scene(j, "step.json", ".");
  const SceneFeatures features = analyse_scene(scene, RenderMode::Phong);
  ASSERT_TRUE(features.lights && features.reflection);
  Runtime& rt = test::runtime();
  auto& ctx = rt.context();
  const BuiltProgram built = rt.build_file("integrator_phong.cl", features.build_options());
  const WideBvh no_bvh;  // shading does not traverse
  const DeviceScene device_scene(ctx, scene, no_bvh, features);
  FilmRig rig(film_options(2, 1));  // only for its film; the stage is bound below

  // Two rays: one hitting the top of the sphere straight down, one missing.
  PathRecord rays[2] = {};
  rays[0].origin = cs_float4{0, 3, 0, 0};
  rays[0].dir = cs_float4{0, -1, 0, 0};
  rays[0].throughput = cs_float4{1, 1, 1, 0};
  rays[0].pixel = 0;
  rays[1].origin = cs_float4{5, 3, 0, 0};
  rays[1].dir = cs_float4{0, 0, 1, 0};
  rays[1].throughput = cs_float4{0.5f, 0.5f, 0.5f, 0};
  rays[1].pixel = 1;
  const std::vector<Hit> hits = {Hit{2.0f, 0.0f, 0.0f, (PRIM_SPHERE << PRIM_TYPE_SHIFT) | 0u}, no_hit()};
  DeviceQueue in(ctx, path_record_layout(), 2), next(ctx, path_record_layout(), 4), shadow(ctx, shadow_record_layout(), 2);
  auto& q = rt.queue();
  const cl_uint two = 2, zero = 0;
  q.enqueueWriteBuffer(in.count(), CL_TRUE, 0, 4, &two);
  q.enqueueWriteBuffer(next.count(), CL_TRUE, 0, 4, &zero);
  q.enqueueWriteBuffer(shadow.count(), CL_TRUE, 0, 4, &zero);
  const cs_float4 origins[2] = {rays[0].origin, rays[1].origin}, dirs[2] = {rays[0].dir, rays[1].dir},
                  weights[2] = {rays[0].throughput, rays[1].throughput};
  const cl_uint pixel_ids[2] = {0, 1}, depths[2] = {0, 0};
  q.enqueueWriteBuffer(in.field("origin"), CL_TRUE, 0, sizeof origins, origins);
  q.enqueueWriteBuffer(in.field("dir"), CL_TRUE, 0, sizeof dirs, dirs);
  q.enqueueWriteBuffer(in.field("throughput"), CL_TRUE, 0, sizeof weights, weights);
  q.enqueueWriteBuffer(in.field("pixel"), CL_TRUE, 0, sizeof pixel_ids, pixel_ids);
  q.enqueueWriteBuffer(in.field("depth"), CL_TRUE, 0, sizeof depths, depths);
  const cl::Buffer hit_buffer = upload_buffer(ctx, hits);
  const std::vector<Light> lights = whitted_lights(scene);
  const cl::Buffer light_buffer = upload_buffer(ctx, lights);

  ShadeParams params{};
  params.background = to_float4(scene.background);
  params.ambient_light = cs_float4{1, 1, 1, 0};
  params.light_count = 1;
  params.max_depth = 2;
  params.ray_capacity = 4;
  params.min_weight = 1e-4f;
  StageKernel shade(built.program, "shade_surface_phong");
  KernelArgs args(shade);
  device_scene.bind_surfaces(args).arg("lights", light_buffer).arg("params", params).queue("in", in).arg("hits", hit_buffer);
  // The wave loop's counters: one the stage clears (seeded non-zero), the
  // rays it traced (2).
  const cl_uint seven = 7;
  cl::Buffer cleared(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, size_t(4), const_cast<cl_uint*>(&seven));
  cl::Buffer traced(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, size_t(4), const_cast<cl_uint*>(&zero));
  rig.film.bind(args)
      .queue("next", next)
      .arg("cleared_count", cleared)
      .queue("shadow", shadow)
      .arg("rays_traced", traced)
      .finish();
  q.enqueueNDRangeKernel(shade.kernel, cl::NullRange, cl::NDRange(64), cl::NDRange(64));
  rig.film.accumulate_pass(rig.launcher);
  q.finish();

  const Material& m = scene.materials[0];
  const float local = 1.0f - 0.25f;
  // Film: pixel 0 the ambient term (ka x diffuse colour, the local share of
  // the weight), pixel 1 the background times its weight.
  const ImageF film = rig.film.mean();
  for (int c = 0; c < 3; ++c) {
    const float diffuse = (&m.diffuse.x)[c];
    EXPECT_NEAR(film.rgb[c], local * m.ka * diffuse, 1e-6f) << c;
    EXPECT_NEAR(film.rgb[3 + c], 0.5f * (&scene.background.x)[c], 1e-6f) << c;
  }
  cl_uint next_count = 0, empty_slot_pixel = 0, cleared_value = 1, traced_value = 0, shadow_count = 0;
  q.enqueueReadBuffer(next.count(), CL_TRUE, 0, 4, &next_count);
  ASSERT_EQ(next_count, 1u);
  q.enqueueReadBuffer(cleared, CL_TRUE, 0, 4, &cleared_value);
  q.enqueueReadBuffer(traced, CL_TRUE, 0, 4, &traced_value);
  q.enqueueReadBuffer(shadow.count(), CL_TRUE, 0, 4, &shadow_count);
  EXPECT_EQ(cleared_value, 0u);
  EXPECT_EQ(traced_value, 2u);
  EXPECT_EQ(shadow_count, 2u);  // two rays, one light: two addressed slots
  // Shadow slots are addressed (ray i, light l at i * lights + l): the hit
  // fills slot 0, the miss leaves slot 1 marked empty.
  q.enqueueReadBuffer(shadow.field("pixel"), CL_TRUE, 4, 4, &empty_slot_pixel);
  EXPECT_EQ(empty_slot_pixel, 0xFFFFFFFFu);
  cs_float4 s_origin, s_dir, s_contribution, n_origin, n_dir, n_weight;
  cl_uint s_pixel, n_pixel, n_depth;
  float s_tmax;
  q.enqueueReadBuffer(shadow.field("origin"), CL_TRUE, 0, 16, &s_origin);
  q.enqueueReadBuffer(shadow.field("dir"), CL_TRUE, 0, 16, &s_dir);
  q.enqueueReadBuffer(shadow.field("contribution"), CL_TRUE, 0, 16, &s_contribution);
  q.enqueueReadBuffer(shadow.field("pixel"), CL_TRUE, 0, 4, &s_pixel);
  q.enqueueReadBuffer(shadow.field("tmax"), CL_TRUE, 0, 4, &s_tmax);
  q.enqueueReadBuffer(next.field("origin"), CL_TRUE, 0, 16, &n_origin);
  q.enqueueReadBuffer(next.field("dir"), CL_TRUE, 0, 16, &n_dir);
  q.enqueueReadBuffer(next.field("throughput"), CL_TRUE, 0, 16, &n_weight);
  q.enqueueReadBuffer(next.field("pixel"), CL_TRUE, 0, 4, &n_pixel);
  q.enqueueReadBuffer(next.field("depth"), CL_TRUE, 0, 4, &n_depth);

  // Shadow ray: leaves just above (0, 1, 0) toward the light, ends short of it;
  // n.l = n.h = 1, so Blinn-Phong gives I (kd diffuse + ks specular) x local.
  EXPECT_NEAR(s_origin.y, 1.0f, 1e-4f);
  EXPECT_GT(s_origin.y, 1.0f);
  EXPECT_NEAR(s_tmax, 4.0f, 1e-3f);
  EXPECT_LT(s_tmax, 4.0f);
  EXPECT_EQ(to_vec3(s_dir), glm::vec3(0, 1, 0));
  EXPECT_EQ(s_pixel, 0u);
  for (int c = 0; c < 3; ++c) {
    const float want = local * 2.0f * (m.diffuse.w * (&m.diffuse.x)[c] + m.specular.w * (&m.specular.x)[c]);
    EXPECT_NEAR((&s_contribution.x)[c], want, 1e-5f) << c;
  }
  // Mirror child: straight back up, weight 0.25, depth 1, same pixel.
  EXPECT_GT(n_origin.y, 1.0f);
  EXPECT_NEAR(n_origin.y, 1.0f, 1e-4f);
  EXPECT_NEAR(glm::length(to_vec3(n_dir) - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_EQ(to_vec3(n_weight), glm::vec3(0.25f));
  EXPECT_EQ(n_pixel, 0u);
  EXPECT_EQ(n_depth, 1u);
}

// ------------------------------------------------------------------ render-level

using test::write_scene;

// The file's rendermode is the default, --mode wins; each mode runs its own
// integrator.
TEST(RenderCore, TheModeIsChosenAtRenderTime) {
  const std::string scene = write_scene("path.json", R"({"rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -3], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 40},
    "scene": {"backgroundcolor": [0.5, 0.5, 0.5], "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]}})");
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  o.spp = 2;
  auto path = prepare_session(o);
  EXPECT_EQ(path->mode, RenderMode::Path);
  EXPECT_STREQ(path->renderer->integrator().name(), "path");
  EXPECT_EQ(path->settings.passes, 2);
  o.mode = RenderMode::Binary;  // the CLI's choice wins over the file's
  const auto session = prepare_session(o);
  EXPECT_EQ(session->mode, RenderMode::Binary);
  EXPECT_EQ(session->scene.mode, RenderMode::Path);
  EXPECT_STREQ(session->renderer->integrator().name(), "binary");
  EXPECT_EQ(session->settings.passes, 1);
  RenderStats stats;
  const ImageF img = session->renderer->render(&stats);
  EXPECT_EQ(img.at(4, 4)[0], 1.0f);  // the sphere fills the centre: red
}

TEST(RenderCore, HdrBackgroundKeepsItsValue) {
  const std::string scene = write_scene("hdr.json", R"({"rendermode": "phong",
    "camera": {"type": "pinhole", "width": 8, "height": 6, "position": [0, 0, -3], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 40},
    "scene": {"backgroundcolor": [1e10, 0.002, 5], "shapes": []}})");
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  const auto session = prepare_session(o);
  RenderStats stats;
  const ImageF img = session->renderer->render(&stats);
  EXPECT_EQ(stats.film.changed(), 0u);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    EXPECT_EQ(img.rgb[3 * i], 1e10f);
    EXPECT_NEAR(img.rgb[3 * i + 1], 0.002f, 1e-6f);
    EXPECT_EQ(img.rgb[3 * i + 2], 5.0f);
  }
}

}  // namespace
}  // namespace caustica
