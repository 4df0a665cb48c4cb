// Host tests of kernels/lib/optics.h, the kernels' own source compiled as
// C++ (kernels/shared/compat.h): fresnel_dielectric against the exact
// unpolarised Fresnel reflectance evaluated in double (over a dense grid of
// incidence cosines and the usual glass/water/diamond ratios, both ways), its
// special cases (eta = 1, total internal reflection, normal and grazing
// incidence), and refract_dir against Snell's law for random directions.
// IEEE float arithmetic, as the kernels are built (correctly rounded
// division and sqrt, no contraction); the images test them on the device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <random>
#include <vector>

#include "lib/optics.h"

namespace caustica {
namespace {

using glm::dvec3;

const double kEtas[] = {1.0 / 2.4, 1.0 / 1.5, 1.0 / 1.33, 1.0, 1.33, 1.5, 2.4};

struct FresnelIn {
  float cos_i, eta;
};
struct FresnelOut {
  float reflectance, cos_t;
};

// The exact unpolarised reflectance from Snell's law, for a given
// sin^2(theta_t) (so the caller can perturb it). Returns 1 and cos_t = 0 on
// total internal reflection.
struct Reference {
  double reflectance, cos_t;
  bool tir;
};
Reference exact_fresnel(double cos_i, double eta, double sin2_t) {
  if (sin2_t >= 1.0) return {1.0, 0.0, true};
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double n1 = eta, n2 = 1.0;  // only the ratio matters
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return {0.5 * (rs * rs + rp * rp), cos_t, false};
}

// Near the critical angle (and for eta = 1 near grazing incidence) the
// reflectance is ill-conditioned in sin^2(theta_t): a few float roundings of
// it move the answer far more than 1e-5. The reference therefore also
// reports how far the answer moves when sin^2(theta_t) is off by a few ulps;
// that spread is added to the tolerance. Away from those cases it is ~0.
struct Expected {
  Reference exact;
  double reflectance_spread, cos_t_spread;
  bool tir_certain, tir_possible;
};
Expected expected_fresnel(float cos_i_f, float eta_f) {
  const double cos_i = cos_i_f, eta = eta_f;  // the float inputs, exactly
  const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  const double rel = 4.0 * 0x1p-24, abs = 2.0 * 0x1p-24 * eta * eta;
  const Reference exact = exact_fresnel(cos_i, eta, sin2_t);
  const Reference lo = exact_fresnel(cos_i, eta, sin2_t * (1.0 - rel) - abs);
  const Reference hi = exact_fresnel(cos_i, eta, sin2_t * (1.0 + rel) + abs);
  Expected e{exact, 0.0, 0.0, lo.tir, hi.tir};
  for (const Reference& r : {lo, hi}) {
    e.reflectance_spread = std::max(e.reflectance_spread, std::abs(r.reflectance - exact.reflectance));
    e.cos_t_spread = std::max(e.cos_t_spread, std::abs(r.cos_t - exact.cos_t));
  }
  return e;
}

// Cosines in [0, 1]: a uniform grid with both ends exactly, plus log-spaced
// values crowding grazing (cos_i -> 0) and normal (cos_i -> 1) incidence.
std::vector<float> cosine_grid() {
  std::vector<float> c;
  const int n = 4096;
  for (int i = 0; i <= n; ++i) c.push_back(static_cast<float>(i) / n);
  for (double e = -7.0; e <= -1.0; e += 0.05) {
    c.push_back(static_cast<float>(std::pow(10.0, e)));
    c.push_back(static_cast<float>(1.0 - std::pow(10.0, e)));
  }
  c.push_back(std::nextafter(1.0f, 0.0f));
  c.push_back(std::numeric_limits<float>::min());
  return c;
}

struct Sample {
  dvec3 d, n;
  float eta;
};
struct Refracted {
  dvec3 t;
  float reflectance;
};

std::vector<FresnelOut> fresnel(const std::vector<FresnelIn>& in) {
  std::vector<FresnelOut> out;
  for (const FresnelIn& f : in) {
    float cos_t = -7.0f;  // a sentinel, so a path that forgets to write it shows
    const float r = fresnel_dielectric(f.cos_i, f.eta, &cos_t);
    out.push_back({r, cos_t});
  }
  return out;
}

// cos_i = -dot(d, n), as the renderer computes it.
std::vector<Refracted> refract(const std::vector<Sample>& samples) {
  std::vector<Refracted> out;
  for (const Sample& s : samples) {
    const float3 d = make_float3(float(s.d.x), float(s.d.y), float(s.d.z));
    const float3 n = make_float3(float(s.n.x), float(s.n.y), float(s.n.z));
    const float cos_i = -dot(d, n);
    float cos_t;
    const float r = fresnel_dielectric(cos_i, s.eta, &cos_t);
    const float3 t = refract_dir(d, n, s.eta, cos_i, cos_t);
    out.push_back({dvec3(t.x, t.y, t.z), r});
  }
  return out;
}

// ------------------------------------------------------------------ Fresnel

TEST(Optics, FresnelMatchesTheExactFormula) {
  std::vector<FresnelIn> in;
  for (double eta : kEtas)
    for (float c : cosine_grid()) in.push_back({c, static_cast<float>(eta)});
  const auto out = fresnel(in);
  int checked = 0, tir = 0;
  for (size_t i = 0; i < in.size(); ++i) {
    const FresnelIn q = in[i];
    const FresnelOut r = out[i];
    const Expected e = expected_fresnel(q.cos_i, q.eta);
    SCOPED_TRACE(::testing::Message() << "cos_i " << q.cos_i << " eta " << q.eta);
    ASSERT_TRUE(std::isfinite(r.reflectance) && std::isfinite(r.cos_t)) << r.reflectance << " " << r.cos_t;
    ASSERT_GE(r.reflectance, 0.0f);
    ASSERT_LE(r.reflectance, 1.0f);
    ASSERT_GE(r.cos_t, 0.0f);
    ASSERT_LE(r.cos_t, 1.0f);
    if (e.tir_certain) {
      ++tir;
      ASSERT_EQ(r.reflectance, 1.0f);
      ASSERT_EQ(r.cos_t, 0.0f);
    } else if (!e.tir_possible) {
      ++checked;
      ASSERT_NEAR(r.reflectance, e.exact.reflectance, 1e-5 + e.reflectance_spread);
      ASSERT_NEAR(r.cos_t, e.exact.cos_t, 1e-5 + e.cos_t_spread);
    }  // else: on the critical angle to within rounding; either answer is right
  }
  // The grid really covers both regimes, and the spread stays an exception.
  EXPECT_GT(checked, 0.95 * (in.size() - tir));
  EXPECT_GT(tir, 1000);
}

TEST(Optics, FresnelIsZeroForMatchedIndices) {
  std::vector<FresnelIn> in;
  for (float c : cosine_grid())
    // cos_i = 0 with eta = 1 is 0/0, no defined answer; so is a cos_i whose
    // square underflows (below ~1e-19), indistinguishable from it.
    if (c * c > 0.0f) in.push_back({c, 1.0f});
  const auto out = fresnel(in);
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_LE(out[i].reflectance, 1e-7f) << "cos_i " << in[i].cos_i;
    EXPECT_EQ(out[i].cos_t, in[i].cos_i) << "cos_i " << in[i].cos_i;
  }
}

TEST(Optics, FresnelTotalInternalReflection) {
  std::vector<FresnelIn> in;
  for (double eta : kEtas) {
    if (eta <= 1.0) continue;
    const double critical = std::sqrt(1.0 - 1.0 / (eta * eta));  // cos of the critical angle
    for (float c : cosine_grid())
      if (c < critical * (1.0 - 1e-5)) in.push_back({c, static_cast<float>(eta)});
  }
  ASSERT_GT(in.size(), 1000u);
  const auto out = fresnel(in);
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i].reflectance, 1.0f) << "cos_i " << in[i].cos_i << " eta " << in[i].eta;
    EXPECT_EQ(out[i].cos_t, 0.0f) << "cos_i " << in[i].cos_i << " eta " << in[i].eta;
  }
}

TEST(Optics, FresnelAtNormalAndGrazingIncidence) {
  std::vector<FresnelIn> in;
  for (double eta : kEtas) {
    in.push_back({1.0f, static_cast<float>(eta)});
    in.push_back({0.0f, static_cast<float>(eta)});
  }
  const auto out = fresnel(in);
  for (size_t i = 0; i < in.size(); ++i) {
    const double eta = in[i].eta;
    SCOPED_TRACE(::testing::Message() << "cos_i " << in[i].cos_i << " eta " << eta);
    EXPECT_TRUE(std::isfinite(out[i].reflectance));
    EXPECT_TRUE(std::isfinite(out[i].cos_t));
    if (in[i].cos_i == 1.0f) {
      const double r0 = (eta - 1.0) * (eta - 1.0) / ((eta + 1.0) * (eta + 1.0));
      EXPECT_NEAR(out[i].reflectance, r0, 1e-6);
      EXPECT_NEAR(out[i].cos_t, 1.0, 1e-6);
    } else if (eta != 1.0) {
      EXPECT_EQ(out[i].reflectance, 1.0f);  // grazing incidence reflects everything
    } else {
      EXPECT_GE(out[i].reflectance, 0.0f);
      EXPECT_LE(out[i].reflectance, 1.0f);
    }
  }
}

// Out-of-range cosines (rounding in -dot(d, n)) are clamped, never NaN.
TEST(Optics, FresnelClampsCosinesOutsideTheUnitInterval) {
  std::vector<FresnelIn> in;
  for (double eta : kEtas)
    for (float c : {-1e-7f, -0.5f, 1.0f + 1e-7f, 1.5f}) in.push_back({c, static_cast<float>(eta)});
  const auto out = fresnel(in);
  for (size_t i = 0; i < in.size(); ++i) {
    const FresnelIn clamped{std::clamp(in[i].cos_i, 0.0f, 1.0f), in[i].eta};
    const FresnelOut want = fresnel({clamped})[0];
    EXPECT_EQ(out[i].reflectance, want.reflectance) << "cos_i " << in[i].cos_i << " eta " << in[i].eta;
    EXPECT_EQ(out[i].cos_t, want.cos_t) << "cos_i " << in[i].cos_i << " eta " << in[i].eta;
  }
}

// --------------------------------------------------------------- refraction

dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const dvec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3) return glm::normalize(v);
  }
}

// Random unit d and n with dot(d, n) < 0, made exactly float and renormalised
// in float so the kernel sees unit vectors to float precision.
std::vector<Sample> random_samples(size_t count, uint32_t seed, bool matched) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> any_eta(0.4, 2.5);
  std::vector<Sample> s;
  while (s.size() < count) {
    const dvec3 n = random_unit(rng);
    dvec3 d = random_unit(rng);
    if (glm::dot(d, n) > 0.0) d = -d;
    const glm::vec3 nf = glm::normalize(glm::vec3(n)), df = glm::normalize(glm::vec3(d));
    if (glm::dot(df, nf) >= 0.0f) continue;
    const float eta = matched ? 1.0f : (s.size() % 2 ? static_cast<float>(kEtas[s.size() / 2 % 7])
                                                     : static_cast<float>(any_eta(rng)));
    s.push_back({dvec3(df), dvec3(nf), eta});
  }
  return s;
}

TEST(Optics, RefractionObeysSnellsLaw) {
  const auto samples = random_samples(20000, 1234, false);
  const auto out = refract(samples);
  int refracted = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    const double cos_i = -glm::dot(s.d, s.n);
    const double sin_i = glm::length(glm::cross(s.d, s.n));
    const double sin2_t = double(s.eta) * s.eta * sin_i * sin_i;
    // Away from the critical angle, where the direction is well defined.
    if (sin2_t > 0.999) continue;
    ++refracted;
    const dvec3 t = out[i].t;
    SCOPED_TRACE(::testing::Message() << "sample " << i << " cos_i " << cos_i << " eta " << s.eta);
    ASSERT_NEAR(glm::length(t), 1.0, 1e-5);
    // In the plane of d and n: no component along their common normal.
    ASSERT_NEAR(glm::dot(t, glm::cross(s.d, s.n)), 0.0, 1e-5);
    // Transmitted to the other side.
    ASSERT_LT(glm::dot(t, s.n), 0.0);
    // Snell: sin_t = eta sin_i, and the tangential part keeps its direction
    // (t_tangent = eta d_tangent), so this is not the mirror image either.
    const double sin_t = glm::length(glm::cross(t, s.n));
    ASSERT_NEAR(sin_t, s.eta * sin_i, 1e-4);
    const dvec3 t_tan = t - glm::dot(t, s.n) * s.n, d_tan = s.d - glm::dot(s.d, s.n) * s.n;
    ASSERT_NEAR(glm::length(t_tan - double(s.eta) * d_tan), 0.0, 1e-4);
  }
  EXPECT_GT(refracted, 10000);  // about half the samples have eta > 1, some of them TIR
}

TEST(Optics, RefractionWithMatchedIndicesKeepsTheDirection) {
  const auto samples = random_samples(20000, 99, true);
  const auto out = refract(samples);
  for (size_t i = 0; i < samples.size(); ++i) {
    const dvec3 diff = out[i].t - samples[i].d;
    ASSERT_LE(glm::length(diff), 1e-6) << "sample " << i << " cos_i " << -glm::dot(samples[i].d, samples[i].n);
    ASSERT_LE(out[i].reflectance, 1e-7f) << "sample " << i;
  }
}

}  // namespace
}  // namespace caustica
