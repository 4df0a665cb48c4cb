// kernels/lib/rng.h, run as kernels: the 2D Sobol sequence is a
// (0,2)-sequence; Sobol-Burley keeps the net property for every power-of-two
// prefix after shuffling and Owen scrambling; pixels and dimension pairs are
// decorrelated; the hash avalanches; and the low-discrepancy samples beat
// independent ones on the integrals a renderer meets (a smooth one and an
// edge), by a margin and by the convergence rate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

#include "tests/support/test_support.h"

namespace caustica {
namespace {

const char* kRngKernels = R"CL(
#include "lib/rng.h"

/* The definition: XOR of the direction numbers of the index's set bits. */
uint sobol_dimension1_by_definition(uint index) {
  uint result = 0u, v = 0x80000000u;
  for (; index != 0u; index >>= 1, v ^= v >> 1)
    if (index & 1u) result ^= v;
  return result;
}

__kernel void sobol_check(__global uint* mismatches, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint index = hash_u32(i) ^ (i << 7);  /* spread over all 32 bits */
  if (sobol_dimension1(index) != sobol_dimension1_by_definition(index) ||
      sobol_dimension1(i) != sobol_dimension1_by_definition(i))
    atomic_inc(mismatches);
}

__kernel void sobol_raw(__global uint2* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = (uint2)(sobol_dimension0(i), sobol_dimension1(i));
}

/* Sample i of pixel p, pair d: out[p * n + i]. */
__kernel void burley(__global float2* out, uint n, uint pixels, uint pair, uint seed) {
  const uint g = get_global_id(0);
  if (g >= n * pixels) return;
  const uint pixel = g / n, i = g % n;
  out[g] = sobol_burley_2d(i, pair, hash3(pixel, 0u, seed));
}

__kernel void independent(__global float2* out, uint n, uint pixels, uint seed) {
  const uint g = get_global_id(0);
  if (g >= n * pixels) return;
  const uint key = hash3(g / n, 1u, seed);
  const uint i = g % n;
  out[g] = (float2)(random_float(key, 2u * i), random_float(key, 2u * i + 1u));
}

__kernel void hash_bits(__global uint* out, __global const uint* in, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = hash_u32(in[i]);
}

__kernel void unit_floats(__global float* out, __global const uint* in, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = unit_float(in[i]);
}
)CL";

cl::Program program() {
  static cl::Program& p = *new cl::Program(test::runtime().build_source("test_rng.cl", kRngKernels, "").program);
  return p;
}

template <typename T, typename... Args>
std::vector<T> run(const char* name, size_t n, size_t local, const Args&... args) {
  Runtime& rt = test::runtime();
  cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, std::max<size_t>(1, n) * sizeof(T));
  cl::Kernel k(program(), name);
  k.setArg(0, out);
  cl_uint index = 1;
  (k.setArg(index++, args), ...);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, local)), cl::NDRange(local));
  std::vector<T> result(n);
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(T), result.data());
  return result;
}

std::vector<cl_float2> burley(uint32_t n, uint32_t pixels, uint32_t pair, uint32_t seed, size_t local = 64) {
  return run<cl_float2>("burley", size_t(n) * pixels, local, cl_uint(n), cl_uint(pixels), cl_uint(pair), cl_uint(seed));
}

// Every elementary interval of volume 2^-m (2^k by 2^(m-k) cells) holds
// exactly one of the 2^m points (cell coordinates given as integers).
bool is_02_net(const std::vector<std::pair<uint64_t, uint64_t>>& cells_at_full_res, int m, int full_bits,
               std::string* why) {
  for (int k = 0; k <= m; ++k) {
    std::vector<int> count(size_t(1) << m, 0);
    for (const auto& [x, y] : cells_at_full_res) {
      const uint64_t cx = x >> (full_bits - k), cy = y >> (full_bits - (m - k));
      ++count[(cx << (m - k)) | cy];
    }
    for (size_t c = 0; c < count.size(); ++c)
      if (count[c] != 1) {
        *why = "m=" + std::to_string(m) + " k=" + std::to_string(k) + " cell " + std::to_string(c) + " holds " +
               std::to_string(count[c]);
        return false;
      }
  }
  return true;
}

TEST(Sobol2D, EveryPowerOfTwoPrefixIsA02Net) {
  const uint32_t n = 1u << 12;
  const auto raw = run<cl_uint2>("sobol_raw", n, 64, cl_uint(n));
  for (int m = 0; m <= 12; ++m) {
    std::vector<std::pair<uint64_t, uint64_t>> pts;
    for (uint32_t i = 0; i < (1u << m); ++i) pts.emplace_back(raw[i].s[0], raw[i].s[1]);
    std::string why;
    EXPECT_TRUE(is_02_net(pts, m, 32, &why)) << why;
  }
  // Not a (0,2)-net by accident: the van der Corput dimension alone is not
  // stratified in y, and a transposed second dimension would break k = 0.
  EXPECT_EQ(raw[1].s[0], 0x80000000u);
  EXPECT_EQ(raw[1].s[1], 0x80000000u);
  EXPECT_EQ(raw[2].s[1], 0xC0000000u);  // v_2 = v_1 ^ (v_1 >> 1)
}

TEST(Sobol2D, FastSecondDimensionEqualsTheDefinition) {
  Runtime& rt = test::runtime();
  const cl_uint zero = 0;
  cl::Buffer mismatches(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, 4, const_cast<cl_uint*>(&zero));
  cl::Kernel k(program(), "sobol_check");
  // Each index is checked on its own: 2^14 of them on Oclgrind.
  const cl_uint n = cl_uint(test::sized(1u << 22, 1u << 14));
  k.setArg(0, mismatches);
  k.setArg(1, n);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n), cl::NDRange(64));
  cl_uint count = 0;
  rt.queue().enqueueReadBuffer(mismatches, CL_TRUE, 0, 4, &count);
  EXPECT_EQ(count, 0u);
}

TEST(SobolBurley, PrefixesStayNetsAfterShufflingAndScrambling) {
  const uint32_t n = 1u << 10;
  for (uint32_t seed : {1u, 7u, 12345u})
    for (uint32_t pair : {0u, 1u, 5u}) {
      const auto s = burley(n, 3, pair, seed);
      for (uint32_t pixel = 0; pixel < 3; ++pixel)
        for (int m = 0; m <= 10; ++m) {
          std::vector<std::pair<uint64_t, uint64_t>> pts;
          for (uint32_t i = 0; i < (1u << m); ++i) {
            const cl_float2 p = s[size_t(pixel) * n + i];
            ASSERT_GE(p.s[0], 0.0f);
            ASSERT_LT(p.s[0], 1.0f);
            ASSERT_GE(p.s[1], 0.0f);
            ASSERT_LT(p.s[1], 1.0f);
            pts.emplace_back(uint64_t(p.s[0] * 16777216.0f), uint64_t(p.s[1] * 16777216.0f));
          }
          std::string why;
          ASSERT_TRUE(is_02_net(pts, m, 24, &why)) << "seed " << seed << " pair " << pair << " pixel " << pixel << ": "
                                                   << why;
        }
    }
}

TEST(SobolBurley, PixelsAndPairsAreDecorrelatedAndUniform) {
  // Sample 0 of 2^16 pixels: uniform over the square (chi-square on 16 x 16
  // cells, 255 degrees of freedom: 99.9% quantile ~ 330). 2^12 pixels on
  // Oclgrind still expect 16 a cell, and the quantile is the same.
  const uint32_t pixels = uint32_t(test::sized(1u << 16, 1u << 12));
  const auto first = burley(1, pixels, 0, 99);
  std::vector<int> cells(256, 0);
  for (const cl_float2& p : first) ++cells[int(p.s[0] * 16) * 16 + int(p.s[1] * 16)];
  const double expected = pixels / 256.0;
  double chi2 = 0.0;
  for (int c : cells) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 330.0);
  // Neighbouring pixels, and two pairs of one pixel, are uncorrelated.
  auto correlation = [](const std::vector<double>& a, const std::vector<double>& b) {
    const double ma = std::accumulate(a.begin(), a.end(), 0.0) / a.size();
    const double mb = std::accumulate(b.begin(), b.end(), 0.0) / b.size();
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      sab += (a[i] - ma) * (b[i] - mb);
      saa += (a[i] - ma) * (a[i] - ma);
      sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
  };
  // 512 pixels on Oclgrind, where 0.02 would be 1.4 standard errors
  // (1 / sqrt(pairs)): the bound is never under 4 of them.
  const uint32_t n = 64, count = uint32_t(test::sized(4096, 512));
  const auto pair0 = burley(n, count, 0, 3), pair1 = burley(n, count, 1, 3);
  std::vector<double> px, next_px, other_pair;
  for (uint32_t pixel = 0; pixel + 1 < count; ++pixel)
    for (uint32_t i = 0; i < n; i += 7) {
      px.push_back(pair0[size_t(pixel) * n + i].s[0]);
      next_px.push_back(pair0[size_t(pixel + 1) * n + i].s[0]);
      other_pair.push_back(pair1[size_t(pixel) * n + i].s[0]);
    }
  const double bound = std::max(0.02, 4.0 / std::sqrt(double(px.size())));
  EXPECT_LT(std::fabs(correlation(px, next_px)), bound);
  EXPECT_LT(std::fabs(correlation(px, other_pair)), bound);
}

TEST(SobolBurley, SameBitsForAnyWorkGroupSize) {
  const auto a = burley(256, 64, 2, 5, 1), b = burley(256, 64, 2, 5, 64);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(cl_float2)));
}

// RMS error over many pixels of the estimate of an integral over the unit
// square: a smooth integrand and a disk edge (what pixel and light samples
// see). Sobol-Burley must beat independent samples clearly at 256 samples
// and converge faster than N^-1/2 between 16 and 256.
TEST(SobolBurley, BeatsIndependentSamplesOnSmoothAndEdgeIntegrands) {
  struct Integrand {
    const char* name;
    double (*f)(double, double);
    double exact;
  };
  const double pi = 3.141592653589793;
  const Integrand integrands[] = {
      {"smooth", [](double x, double y) { return std::sin(3.141592653589793 * x) * std::sin(3.141592653589793 * y); },
       4.0 / (pi * pi)},
      {"edge", [](double x, double y) { return x * x + y * y < 1.0 ? 1.0 : 0.0; }, pi / 4.0},
  };
  const uint32_t pixels = 512;
  for (const Integrand& g : integrands) {
    double rmse[2][2];  // [sampler][16 or 256 samples]
    for (int sampler = 0; sampler < 2; ++sampler)
      for (int which = 0; which < 2; ++which) {
        const uint32_t n = which == 0 ? 16 : 256;
        const auto s = sampler == 0 ? burley(n, pixels, 0, 11)
                                    : run<cl_float2>("independent", size_t(n) * pixels, 64, cl_uint(n),
                                                     cl_uint(pixels), cl_uint(11));
        double se = 0.0;
        for (uint32_t p = 0; p < pixels; ++p) {
          double sum = 0.0;
          for (uint32_t i = 0; i < n; ++i) sum += g.f(s[size_t(p) * n + i].s[0], s[size_t(p) * n + i].s[1]);
          se += (sum / n - g.exact) * (sum / n - g.exact);
        }
        rmse[sampler][which] = std::sqrt(se / pixels);
      }
    std::printf("[measure] %s: RMSE at 16 / 256 spp: Sobol-Burley %.2e / %.2e, independent %.2e / %.2e\n", g.name,
                rmse[0][0], rmse[0][1], rmse[1][0], rmse[1][1]);
    EXPECT_LT(rmse[0][1], 0.4 * rmse[1][1]) << g.name;
    // Independent: x4 at 16x the samples (N^-1/2); Sobol-Burley at least x6.
    EXPECT_GT(rmse[0][0] / rmse[0][1], 6.0) << g.name;
    EXPECT_GT(rmse[1][0] / rmse[1][1], 3.0) << g.name;
    EXPECT_LT(rmse[1][0] / rmse[1][1], 5.3) << g.name;
  }
}

TEST(Hash, AvalanchesAndFloatsStayBelowOne) {
  std::vector<cl_uint> in;
  for (uint32_t i = 0; i < 4096; ++i)
    for (int bit = 0; bit < 32; bit += 5) {
      in.push_back(i * 2654435761u);
      in.push_back((i * 2654435761u) ^ (1u << bit));
    }
  Runtime& rt = test::runtime();
  cl::Buffer input(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * 4, in.data());
  const auto out = run<cl_uint>("hash_bits", in.size(), 64, input, cl_uint(in.size()));
  double flipped = 0.0;
  for (size_t i = 0; i < out.size(); i += 2) flipped += __builtin_popcount(out[i] ^ out[i + 1]);
  const double mean = flipped / (out.size() / 2) / 32.0;
  EXPECT_GT(mean, 0.48);
  EXPECT_LT(mean, 0.52);

  const std::vector<cl_uint> edges = {0u, 1u, 0xFFu, 0x100u, 0x7FFFFFFFu, 0xFFFFFF00u, 0xFFFFFFFFu};
  cl::Buffer e(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, edges.size() * 4,
               const_cast<cl_uint*>(edges.data()));
  const auto f = run<cl_float>("unit_floats", edges.size(), 64, e, cl_uint(edges.size()));
  EXPECT_EQ(f[0], 0.0f);
  EXPECT_EQ(f[1], 0.0f);  // below 2^-24
  EXPECT_EQ(f[3], 0x1.0p-24f);
  EXPECT_LT(f[6], 1.0f);
  EXPECT_EQ(f[6], 1.0f - 0x1.0p-24f);
}

}  // namespace
}  // namespace caustica
