// kernels/lib/rng.h on the host (the kernels' source, kernels/shared/
// compat.h): the 2D Sobol sequence is a
// (0,2)-sequence; Sobol-Burley keeps the net property for every power-of-two
// prefix after shuffling and Owen scrambling; pixels and dimension pairs are
// decorrelated; the hash avalanches; and the low-discrepancy samples beat
// independent ones on the integrals a renderer meets (a smooth one and an
// edge), by a margin and by the convergence rate. That the device draws the
// same bits for any work-group size is the images' test (PathTracer's and
// stiff_determinism's).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

#include "lib/rng.h"

namespace caustica {
namespace {

/* The definition: XOR of the direction numbers of the index's set bits. */
uint32_t sobol_dimension1_by_definition(uint32_t index) {
  uint32_t result = 0u, v = 0x80000000u;
  for (; index != 0u; index >>= 1, v ^= v >> 1)
    if (index & 1u) result ^= v;
  return result;
}

/* Sample i of pixel p, dimension pair `pair`: out[p * n + i]. */
std::vector<float2> burley(uint32_t n, uint32_t pixels, uint32_t pair, uint32_t seed) {
  std::vector<float2> out;
  for (uint32_t pixel = 0; pixel < pixels; ++pixel)
    for (uint32_t i = 0; i < n; ++i) out.push_back(sobol_burley_2d(i, pair, hash3(pixel, 0u, seed)));
  return out;
}

std::vector<float2> independent(uint32_t n, uint32_t pixels, uint32_t seed) {
  std::vector<float2> out;
  for (uint32_t pixel = 0; pixel < pixels; ++pixel) {
    const uint32_t key = hash3(pixel, 1u, seed);
    for (uint32_t i = 0; i < n; ++i) out.push_back(make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u)));
  }
  return out;
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
  for (int m = 0; m <= 12; ++m) {
    std::vector<std::pair<uint64_t, uint64_t>> pts;
    for (uint32_t i = 0; i < (1u << m); ++i) pts.emplace_back(sobol_dimension0(i), sobol_dimension1(i));
    std::string why;
    EXPECT_TRUE(is_02_net(pts, m, 32, &why)) << why;
  }
  // Not a (0,2)-net by accident: the van der Corput dimension alone is not
  // stratified in y, and a transposed second dimension would break k = 0.
  EXPECT_EQ(sobol_dimension0(1), 0x80000000u);
  EXPECT_EQ(sobol_dimension1(1), 0x80000000u);
  EXPECT_EQ(sobol_dimension1(2), 0xC0000000u);  // v_2 = v_1 ^ (v_1 >> 1)
}

TEST(Sobol2D, FastSecondDimensionEqualsTheDefinition) {
  uint32_t mismatches = 0;
  for (uint32_t i = 0; i < (1u << 22); ++i) {
    const uint32_t index = hash_u32(i) ^ (i << 7); /* spread over all 32 bits */
    mismatches += sobol_dimension1(index) != sobol_dimension1_by_definition(index);
    mismatches += sobol_dimension1(i) != sobol_dimension1_by_definition(i);
  }
  EXPECT_EQ(mismatches, 0u);
}

// The shade stage draws a vertex's three pairs in vector lanes
// (sobol_burley_2d_x3): the same bits as three scalar draws, for indices,
// pairs and seeds across their ranges.
TEST(SobolBurley, ThreePairsInVectorLanesAreTheScalarBits) {
  uint32_t mismatches = 0;
  for (uint32_t i = 0; i < (1u << 16); ++i) {
    const uint32_t index = i < 4096u ? i : hash_u32(i) ^ (i << 9);
    const uint32_t first_pair = 2u + 3u * (i % 70u);
    const uint32_t pixel_seed = hash3(i * 2654435761u, 0u, i >> 3);
    float2 got[3];
    sobol_burley_2d_x3(index, first_pair, pixel_seed, &got[0], &got[1], &got[2]);
    for (uint32_t k = 0; k < 3u; ++k) {
      const float2 want = sobol_burley_2d(index, first_pair + k, pixel_seed);
      mismatches += std::memcmp(&got[k].x, &want.x, sizeof(float)) != 0 || std::memcmp(&got[k].y, &want.y, sizeof(float)) != 0;
    }
  }
  EXPECT_EQ(mismatches, 0u);
  float2 a, b, c;  // the independent sampler takes the same three pairs one by one
  pixel_samples_2d_x3(SAMPLER_INDEPENDENT, 5u, 8u, 77u, &a, &b, &c);
  EXPECT_EQ(c.x, pixel_sample_2d(SAMPLER_INDEPENDENT, 5u, 10u, 77u).x);
  EXPECT_EQ(a.y, pixel_sample_2d(SAMPLER_INDEPENDENT, 5u, 8u, 77u).y);
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
            const float2 p = s[size_t(pixel) * n + i];
            ASSERT_GE(p.x, 0.0f);
            ASSERT_LT(p.x, 1.0f);
            ASSERT_GE(p.y, 0.0f);
            ASSERT_LT(p.y, 1.0f);
            pts.emplace_back(uint64_t(p.x * 16777216.0f), uint64_t(p.y * 16777216.0f));
          }
          std::string why;
          ASSERT_TRUE(is_02_net(pts, m, 24, &why)) << "seed " << seed << " pair " << pair << " pixel " << pixel << ": "
                                                   << why;
        }
    }
}

TEST(SobolBurley, PixelsAndPairsAreDecorrelatedAndUniform) {
  // Sample 0 of 2^16 pixels: uniform over the square (chi-square on 16 x 16
  // cells, 255 degrees of freedom: 99.9% quantile ~ 330).
  const uint32_t pixels = 1u << 16;
  const auto first = burley(1, pixels, 0, 99);
  std::vector<int> cells(256, 0);
  for (const float2& p : first) ++cells[int(p.x * 16) * 16 + int(p.y * 16)];
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
  // The bound is never under 4 standard errors (1 / sqrt(pairs)).
  const uint32_t n = 64, count = 4096;
  const auto pair0 = burley(n, count, 0, 3), pair1 = burley(n, count, 1, 3);
  std::vector<double> px, next_px, other_pair;
  for (uint32_t pixel = 0; pixel + 1 < count; ++pixel)
    for (uint32_t i = 0; i < n; i += 7) {
      px.push_back(pair0[size_t(pixel) * n + i].x);
      next_px.push_back(pair0[size_t(pixel + 1) * n + i].x);
      other_pair.push_back(pair1[size_t(pixel) * n + i].x);
    }
  const double bound = std::max(0.02, 4.0 / std::sqrt(double(px.size())));
  EXPECT_LT(std::fabs(correlation(px, next_px)), bound);
  EXPECT_LT(std::fabs(correlation(px, other_pair)), bound);
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
        const auto s = sampler == 0 ? burley(n, pixels, 0, 11) : independent(n, pixels, 11);
        double se = 0.0;
        for (uint32_t p = 0; p < pixels; ++p) {
          double sum = 0.0;
          for (uint32_t i = 0; i < n; ++i) sum += g.f(s[size_t(p) * n + i].x, s[size_t(p) * n + i].y);
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
  double flipped = 0.0;
  int pairs = 0;
  for (uint32_t i = 0; i < 4096; ++i)
    for (int bit = 0; bit < 32; bit += 5) {
      flipped += __builtin_popcount(hash_u32(i * 2654435761u) ^ hash_u32((i * 2654435761u) ^ (1u << bit)));
      ++pairs;
    }
  const double mean = flipped / pairs / 32.0;
  EXPECT_GT(mean, 0.48);
  EXPECT_LT(mean, 0.52);

  EXPECT_EQ(unit_float(0u), 0.0f);
  EXPECT_EQ(unit_float(1u), 0.0f);  // below 2^-24
  EXPECT_EQ(unit_float(0x100u), 0x1.0p-24f);
  EXPECT_LT(unit_float(0xFFFFFFFFu), 1.0f);
  EXPECT_EQ(unit_float(0xFFFFFFFFu), 1.0f - 0x1.0p-24f);
}

}  // namespace
}  // namespace caustica
