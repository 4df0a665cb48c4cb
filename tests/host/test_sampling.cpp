// Host tests of kernels/lib/sampling.h and lib/ggx.h, the kernels' own source
// compiled as C++ (kernels/shared/compat.h).
//
// The warps are checked by a chi-square goodness-of-fit test in the style of
// pbrt-v4 and Mitsuba 3: N samples are drawn from independent uniforms
// (random_float of lib/rng.h keyed by the sample index, so every run sees the
// same numbers and the tests cannot flake); they are histogrammed over a
// 2D parametrisation of the sample space mapped onto the unit square; the
// expected count of each cell is N times the integral of the claimed density
// over the cell, by 5x5-point Gauss-Legendre in the parametrisation, with the
// density evaluated by the header's pdf function (so the library's pdf is
// what is tested, against the library's warp). Cells expecting
// fewer than 5 samples are pooled; the p-value is the regularised upper
// incomplete gamma function Q(dof/2, chi2/2). Every such test also checks
// that the density integrates to 1 within 1e-3 over the parametrised domain.
//
// Parametrisations (unit square <- sample space):
//  - sphere: (cos theta in [-1, 1], phi in [0, 2 pi)), 32 x 64 cells;
//  - cone: ((1 - cos theta) / (1 - cos_max), phi), 32 x 64 cells, so that a
//    tiny cone gets the same resolution as a wide one;
//  - GGX visible normals: the sphere parametrisation of the *stretched*
//    normal m' = normalize(m.x / alpha, m.y / alpha, m.z) (the configuration
//    in which every alpha looks like alpha = 1), 32 x 64 cells, with the
//    Jacobian d omega_m / d omega_m' = alpha^2 / |(alpha m'.x, alpha m'.y,
//    m'.z)|^3. The narrow lobe of a small alpha is thereby spread over the
//    whole hemisphere of cells: every alpha is tested with the same power;
//  - disk: (r^2, angle), 32 x 64; triangle: a 64 x 64 grid over (b1, b2)
//    whose diagonal cells are exact half cells; parallelogram: (s, t) from
//    the least-squares inverse, 32 x 32.
//
// The single chi-square tests need p > 0.01; a TEST running k of them needs
// p > 1 - 0.99^(1/k) of each (Sidak).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <glm/glm.hpp>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lib/ggx.h"
#include "lib/rng.h"
#include "lib/sampling.h"
#include "tests/support/chi_square.h"

namespace caustica {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kSamples = 1000000;
size_t fit_samples() { return kSamples; }

enum Warp : cl_uint { kCosine = 0, kSphere, kCone, kGgxVndf, kDisk, kTriangle, kRectangle };

cl_float4 f4(double x, double y, double z, double w = 0.0) {
  return {{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z), static_cast<float>(w)}};
}
cl_float4 f4(const dvec3& v) { return f4(v.x, v.y, v.z); }
dvec3 d3(const cl_float4& v) { return dvec3(v.s[0], v.s[1], v.s[2]); }

// ------------------------------------------------------------ the library

struct WarpParams {
  Warp mode;
  float param = 0.0f;  // 1 - cos_max of the cone, alpha of GGX
  cl_float4 a{}, b{}, c{};  // a: wo of GGX, the centre of the rectangle; b, c: its edges
};

float3 xyz(const cl_float4& v) { return make_float3(v.s[0], v.s[1], v.s[2]); }
cl_float4 f4(float3 v) { return f4(v.x, v.y, v.z); }

cl_float4 warp(const WarpParams& w, float2 u) {
  switch (w.mode) {
    case kCosine: return f4(sample_cosine_hemisphere(u));
    case kSphere: return f4(sample_uniform_sphere(u));
    case kCone: return f4(sample_uniform_cone(u, w.param));
    case kGgxVndf: return f4(ggx_sample_visible_normal(xyz(w.a), w.param, u));
    case kDisk: {
      const float2 d = sample_concentric_disk(u);
      return f4(d.x, d.y, 0.0);
    }
    case kTriangle: {
      const float2 b = sample_triangle_barycentrics(u);
      return f4(b.x, b.y, 0.0);
    }
    default: return f4(sample_rectangle(xyz(w.a), xyz(w.b), xyz(w.c), u));
  }
}

std::vector<cl_float4> sample_random(const WarpParams& w, cl_uint key, size_t n) {
  std::vector<cl_float4> out;
  for (uint32_t i = 0; i < n; ++i)
    out.push_back(warp(w, make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u))));
  return out;
}

std::vector<cl_float4> sample_at(const WarpParams& w, const std::vector<cl_float2>& u) {
  std::vector<cl_float4> out;
  for (const cl_float2& v : u) out.push_back(warp(w, make_float2(v.s[0], v.s[1])));
  return out;
}

/* The header's density of the warp at the direction p. The uniform sphere
 * has no pdf function: its documented 1 / (4 pi). The cone's density is
 * pdf_uniform_cone inside the cone, 0 outside. */
std::vector<double> library_pdf(const WarpParams& w, const std::vector<cl_float4>& points) {
  std::vector<double> out;
  for (const cl_float4& p : points) {
    const float3 d = xyz(p);
    float r = 0.0f;
    switch (w.mode) {
      case kCosine: r = pdf_cosine_hemisphere(d.z); break;
      case kSphere: r = 0.25f * M_1_PI_F; break;
      case kCone: r = (d.x * d.x + d.y * d.y) / (1.0f + d.z) <= w.param * 1.00001f ? pdf_uniform_cone(w.param) : 0.0f; break;
      case kGgxVndf: r = ggx_pdf_visible_normal(xyz(w.a), d, w.param); break;
      default: break;
    }
    out.push_back(r);
  }
  return out;
}

struct GgxValues {
  double d, g1, g2, pdf;
};
// (D(wo), G1(wo), G2(wo, wi), pdf of wi as a visible normal seen from wo).
std::vector<GgxValues> ggx_eval(float alpha, const std::vector<cl_float4>& wo, const std::vector<cl_float4>& wi) {
  std::vector<GgxValues> r;
  for (size_t i = 0; i < wo.size(); ++i) {
    const float3 o = xyz(wo[i]), w = xyz(wi[i]);
    r.push_back({ggx_d(o, alpha), ggx_g1(o, alpha), ggx_g2(o, w, alpha), ggx_pdf_visible_normal(o, w, alpha)});
  }
  return r;
}

using test::ChiSquare;
using test::Density;
using test::Domain;
using test::chi_square_statistic;
using test::chi_square_test;
using test::chi_square_p_value;
using test::gamma_q;
using test::sidak;
using test::sphere_domain;
using test::wrap_unit_angle;
constexpr double kAlphaLevel = test::kChiSquareAlpha;

// ((1 - cos theta) / one_minus_cos_max, phi) of the cone around +z.
Domain cone_domain(double one_minus_cos_max) {
  Domain d{32, 64, {}, {}};
  d.to_unit = [one_minus_cos_max](const cl_float4& s, double* x1, double* x2) {
    const dvec3 v = d3(s);
    if (v.z <= 0.0 && one_minus_cos_max <= 1.0) return false;
    const double one_minus_cos = (v.x * v.x + v.y * v.y) / (1.0 + v.z);  // no cancellation
    const double x = one_minus_cos / one_minus_cos_max;
    if (x > 1.0 + 1e-4) return false;
    *x1 = std::min(x, 1.0);
    *x2 = wrap_unit_angle(v.x, v.y);
    return true;
  };
  d.from_unit = [one_minus_cos_max](double x1, double x2, double* jacobian) {
    const double omc = x1 * one_minus_cos_max, s = std::sqrt(omc * (2.0 - omc)), phi = 2.0 * kPi * x2;
    *jacobian = 2.0 * kPi * one_minus_cos_max;
    return f4(s * std::cos(phi), s * std::sin(phi), 1.0 - omc);
  };
  return d;
}

// The sphere parametrisation of the stretched normal m' (see the top).
Domain stretched_domain(double alpha) {
  Domain d{32, 64, {}, {}};
  d.to_unit = [alpha](const cl_float4& s, double* x1, double* x2) {
    const dvec3 v = glm::normalize(dvec3(s.s[0] / alpha, s.s[1] / alpha, s.s[2]));
    *x1 = std::clamp(0.5 * (v.z + 1.0), 0.0, 1.0);
    *x2 = wrap_unit_angle(v.x, v.y);
    return true;
  };
  d.from_unit = [alpha](double x1, double x2, double* jacobian) {
    const double z = 2.0 * x1 - 1.0, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * x2;
    const dvec3 m(alpha * r * std::cos(phi), alpha * r * std::sin(phi), z);
    const double len = glm::length(m);
    *jacobian = 4.0 * kPi * alpha * alpha / (len * len * len);
    return f4(m / len);
  };
  return d;
}

Density library_density(const WarpParams& w) {
  return [w](const std::vector<cl_float4>& points) { return library_pdf(w, points); };
}

ChiSquare run_chi_square(const WarpParams& w, const Domain& dom, cl_uint key) {
  return chi_square_test(sample_random(w, key, fit_samples()), dom, library_density(w));
}

dvec3 direction_at(double theta_degrees) {
  const double t = theta_degrees * kPi / 180.0;
  return dvec3(std::sin(t), 0.0, std::cos(t));
}

// Checks one chi-square result against the threshold p_min.
void expect_fits(const ChiSquare& r, double p_min) {
  EXPECT_EQ(r.outside, 0u) << r.describe();
  EXPECT_LT(r.max_norm_error, 1e-5) << r.describe();
  EXPECT_NEAR(r.integral, 1.0, 1e-3) << r.describe();
  EXPECT_GT(r.p, p_min) << r.describe();
}

// ------------------------------------------------------------------ tests

// The statistics themselves, against closed forms.
TEST(ChiSquareHarness, IncompleteGammaMatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(gamma_q(1.0, x), std::exp(-x), 1e-12) << x;
    EXPECT_NEAR(gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-12) << x;
    EXPECT_NEAR(gamma_q(2.0, x), (1.0 + x) * std::exp(-x), 1e-12) << x;
  }
  // Large dof: chi2 = dof is near the median (p ~ 0.5); the tails behave.
  EXPECT_NEAR(chi_square_p_value(2000.0, 2000), 0.4955, 2e-3);
  EXPECT_LT(chi_square_p_value(2300.0, 2000), 1e-4);
  EXPECT_GT(chi_square_p_value(1700.0, 2000), 0.9999);
}

// The harness can fail: a density 5% too large, and one of the wrong shape,
// are both caught on cosine-weighted samples.
TEST(ChiSquareHarness, RejectsWrongDensities) {
  const WarpParams w{kCosine};
  const std::vector<cl_float4> samples = sample_random(w, 11u, kSamples);
  const ChiSquare right = chi_square_test(samples, sphere_domain(), library_density(w));
  EXPECT_GT(right.p, kAlphaLevel) << right.describe();
  const ChiSquare scaled = chi_square_test(samples, sphere_domain(), [&](const std::vector<cl_float4>& p) {
    std::vector<double> d = library_pdf(w, p);
    for (double& v : d) v *= 1.05;
    return d;
  });
  EXPECT_GT(std::abs(scaled.integral - 1.0), 0.04);
  EXPECT_LT(scaled.p, 1e-6) << scaled.describe();
  const ChiSquare uniform = chi_square_test(samples, sphere_domain(), [](const std::vector<cl_float4>& p) {
    std::vector<double> d;
    for (const cl_float4& v : p) d.push_back(v.s[2] > 0.0f ? 0.5 / kPi : 0.0);  // uniform hemisphere
    return d;
  });
  EXPECT_NEAR(uniform.integral, 1.0, 1e-3);
  EXPECT_LT(uniform.p, 1e-6) << uniform.describe();
}

TEST(SamplingChiSquare, CosineHemisphere) {
  const ChiSquare r = run_chi_square({kCosine}, sphere_domain(), 1u);
  std::cout << "cosine hemisphere: " << r.describe() << "\n";
  expect_fits(r, kAlphaLevel);
}

TEST(SamplingChiSquare, UniformSphere) {
  const ChiSquare r = run_chi_square({kSphere}, sphere_domain(), 2u);
  std::cout << "uniform sphere: " << r.describe() << "\n";
  expect_fits(r, kAlphaLevel);
}

TEST(SamplingChiSquare, UniformCone) {
  const std::vector<float> cones = {1e-3f, 0.1f, 1.0f};
  for (size_t i = 0; i < cones.size(); ++i) {
    WarpParams w{kCone, cones[i]};
    const ChiSquare r = run_chi_square(w, cone_domain(cones[i]), 3u + static_cast<cl_uint>(i));
    std::cout << "cone 1-cos_max " << cones[i] << ": " << r.describe() << "\n";
    SCOPED_TRACE(::testing::Message() << "one_minus_cos_max " << cones[i]);
    expect_fits(r, sidak(static_cast<int>(cones.size())));
  }
}

TEST(SamplingChiSquare, GgxVisibleNormals) {
  // GGX_ALPHA_MIN (1e-3) as well: there the density once lost the lobe to
  // float cancellation (1 - m.z^2 in ggx_d).
  const float alphas[] = {1e-3f, 0.05f, 0.2f, 0.5f, 1.0f};
  const double thetas[] = {0.0, 30.0, 60.0, 85.0};
  const int tests = 20;
  cl_uint key = 100;
  for (float alpha : alphas)
    for (double theta : thetas) {
      WarpParams w{kGgxVndf, alpha, f4(direction_at(theta))};
      const ChiSquare r = run_chi_square(w, stretched_domain(alpha), key++);
      std::cout << "ggx alpha " << alpha << " theta " << theta << ": " << r.describe() << "\n";
      SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " theta_o " << theta);
      expect_fits(r, sidak(tests));
    }
}

TEST(SamplingChiSquare, ConcentricDisk) {
  Domain d{32, 64, {}, {}};
  d.directions = false;
  d.to_unit = [](const cl_float4& s, double* x1, double* x2) {
    const double r2 = double(s.s[0]) * s.s[0] + double(s.s[1]) * s.s[1];
    if (r2 > 1.0 + 1e-6) return false;
    *x1 = std::min(r2, 1.0);
    *x2 = wrap_unit_angle(s.s[0], s.s[1]);
    return true;
  };
  d.from_unit = [](double x1, double x2, double* jacobian) {
    *jacobian = kPi;  // area = (1/2) d(r^2) d(angle)
    const double r = std::sqrt(x1), phi = 2.0 * kPi * x2;
    return f4(r * std::cos(phi), r * std::sin(phi), 0.0);
  };
  const ChiSquare r = chi_square_test(sample_random({kDisk}, 20u, fit_samples()), d, [](const std::vector<cl_float4>& p) {
    return std::vector<double>(p.size(), 1.0 / kPi);  // uniform on the unit disk
  });
  std::cout << "concentric disk: " << r.describe() << "\n";
  expect_fits(r, kAlphaLevel);
}

TEST(SamplingChiSquare, TriangleBarycentrics) {
  // A 64 x 64 grid over (b1, b2): cells with i + j <= n - 2 lie inside the
  // triangle, cells with i + j = n - 1 are cut exactly in half by b1 + b2 = 1.
  const int n = 64;
  const std::vector<cl_float4> s = sample_random({kTriangle}, 21u, fit_samples());
  std::vector<double> observed(n * n, 0.0), expected(n * n, 0.0);
  size_t outside = 0;
  for (const cl_float4& v : s) {
    const double b1 = v.s[0], b2 = v.s[1];
    if (!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6)) {
      ++outside;
      continue;
    }
    const int i = std::min(int(b1 * n), n - 1), j = std::min(int(b2 * n), n - 1);
    observed[i * n + j] += 1.0;
  }
  double integral = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double area = i + j <= n - 2 ? 1.0 / (n * n) : i + j == n - 1 ? 0.5 / (n * n) : 0.0;
      integral += 2.0 * area;  // density 1 / (triangle area 1/2)
      expected[i * n + j] = 2.0 * area * s.size();
    }
  ChiSquare r;
  r.integral = integral;
  r.outside = outside;
  chi_square_statistic(observed, expected, &r);
  std::cout << "triangle: " << r.describe() << "\n";
  expect_fits(r, kAlphaLevel);
}

TEST(SamplingChiSquare, Parallelogram) {
  const dvec3 centre(0.3, -1.2, 2.0), eu(2.0, 0.5, 0.3), ev(-0.4, 1.5, 0.8);
  const double area = glm::length(glm::cross(eu, ev));
  WarpParams w{kRectangle, 0.0f, f4(centre), f4(eu), f4(ev)};
  Domain d{32, 32, {}, {}};
  d.directions = false;
  double max_off_plane = 0.0;
  d.to_unit = [&](const cl_float4& v, double* x1, double* x2) {
    // Least squares (s, t) of p - centre = s eu + t ev.
    const dvec3 p = d3(v) - centre;
    const double a = glm::dot(eu, eu), b = glm::dot(eu, ev), c = glm::dot(ev, ev);
    const double pu = glm::dot(p, eu), pv = glm::dot(p, ev), det = a * c - b * b;
    const double s = (c * pu - b * pv) / det, t = (a * pv - b * pu) / det;
    max_off_plane = std::max(max_off_plane, glm::length(p - s * eu - t * ev));
    if (std::abs(s) > 0.5 + 1e-5 || std::abs(t) > 0.5 + 1e-5) return false;
    *x1 = std::clamp(s + 0.5, 0.0, 1.0);
    *x2 = std::clamp(t + 0.5, 0.0, 1.0);
    return true;
  };
  d.from_unit = [&](double x1, double x2, double* jacobian) {
    *jacobian = area;
    return f4(centre + (x1 - 0.5) * eu + (x2 - 0.5) * ev);
  };
  const ChiSquare r = chi_square_test(sample_random(w, 22u, fit_samples()), d, [&](const std::vector<cl_float4>& p) {
    return std::vector<double>(p.size(), 1.0 / area);  // the documented 1 / |edge_u x edge_v|
  });
  std::cout << "parallelogram: " << r.describe() << "\n";
  expect_fits(r, kAlphaLevel);
  EXPECT_LT(max_off_plane, 1e-5);
}

// ------------------------------------------------------------ GGX identities

// The integral of D(m) m.z over the hemisphere is 1. With t = tan^2 theta /
// alpha^2 and v = t / (1 + t) in [0, 1), D m.z d omega = dv exactly, so the
// midpoint rule in v resolves the peak of any alpha; per unit v the weight of
// D is pi alpha^2 cos^4 theta / (1 - v)^2 = pi alpha^2 / ((1 - v) + alpha^2 v)^2.
TEST(Ggx, NormalDistributionIsNormalised) {
  const int n = 20000;
  for (float alpha : {1e-3f, 0.01f, 0.1f, 0.5f, 1.0f}) {
    const double a2 = double(alpha) * alpha;
    std::vector<cl_float4> m;
    std::vector<double> weight;
    for (int k = 0; k < n; ++k) {
      const double v = (k + 0.5) / n, q = (1.0 - v) + a2 * v;
      m.push_back(f4(std::sqrt(a2 * v / q), 0.0, std::sqrt((1.0 - v) / q)));
      weight.push_back(kPi * a2 / (q * q) / n);
    }
    const auto out = ggx_eval(alpha, m, m);
    double integral = 0.0;
    for (int k = 0; k < n; ++k) integral += out[k].d * weight[k];
    EXPECT_NEAR(integral, 1.0, 1e-3) << "alpha " << alpha;
  }
}

// The visible-normal density integrates to 1 over m, for every wo. The
// integral runs over the stretched hemisphere (as the chi-square test bins),
// where the integrand is a clamped cosine: a fine midpoint grid suffices.
TEST(Ggx, VisibleNormalDensityIsNormalised) {
  const int nz = 256, nphi = 512;
  for (float alpha : {1e-3f, 0.01f, 0.1f, 0.5f, 1.0f})
    for (double theta : {0.0, 30.0, 60.0, 85.0, 89.5}) {
      const dvec3 wo = direction_at(theta);
      std::vector<cl_float4> wos, ms;
      std::vector<double> weight;
      for (int i = 0; i < nz; ++i)
        for (int j = 0; j < nphi; ++j) {
          const double z = (i + 0.5) / nz, r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * (j + 0.5) / nphi;
          const dvec3 m(alpha * r * std::cos(phi), alpha * r * std::sin(phi), z);
          const double len = glm::length(m);
          wos.push_back(f4(wo));
          ms.push_back(f4(m / len));
          weight.push_back(2.0 * kPi * alpha * alpha / (len * len * len) / (double(nz) * nphi));
        }
      const auto out = ggx_eval(alpha, wos, ms);
      double integral = 0.0;
      for (size_t k = 0; k < out.size(); ++k) integral += out[k].pdf * weight[k];
      EXPECT_NEAR(integral, 1.0, 1e-3) << "alpha " << alpha << " theta_o " << theta;
    }
}

// G1 is 1 at normal incidence, matches Smith's closed form, and decreases
// toward grazing incidence.
TEST(Ggx, MaskingDecreasesTowardGrazing) {
  std::vector<cl_float4> w;
  std::vector<double> theta;
  for (int k = 0; k <= 900; ++k) {
    theta.push_back(k * 0.1);
    w.push_back(f4(direction_at(k * 0.1)));
  }
  w.back() = f4(1.0, 0.0, 0.0);  // exactly tangent
  for (float alpha : {1e-3f, 0.05f, 0.2f, 0.5f, 1.0f}) {
    SCOPED_TRACE(::testing::Message() << "alpha " << alpha);
    const auto out = ggx_eval(alpha, w, w);
    EXPECT_EQ(out[0].g1, 1.0);
    for (size_t k = 0; k < out.size(); ++k) {
      const double g1 = out[k].g1;
      ASSERT_TRUE(std::isfinite(g1) && g1 >= 0.0 && g1 <= 1.0) << "theta " << theta[k] << " g1 " << g1;
      if (k > 0) ASSERT_LE(g1, out[k - 1].g1 + 1e-6) << "theta " << theta[k];
      if (k + 1 < out.size()) {
        const dvec3 v = d3(w[k]);  // the float direction, exactly
        const double tan2 = (v.x * v.x + v.y * v.y) / (v.z * v.z);
        const double exact = 2.0 / (1.0 + std::sqrt(1.0 + double(alpha) * alpha * tan2));
        ASSERT_NEAR(g1, exact, 1e-5) << "theta " << theta[k];
      }
    }
    EXPECT_LT(out.back().g1, 1e-6);  // tangent: fully masked
    if (alpha >= 0.05f) EXPECT_LT(out[895].g1, out[0].g1 - 0.05);
  }
}

// Height-correlated G2 lies between the uncorrelated product and the smaller
// of the two G1.
TEST(Ggx, ShadowingMaskingIsBoundedByMasking) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto hemisphere = [&] {
    const double z = uni(rng), r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * uni(rng);
    return f4(r * std::cos(phi), r * std::sin(phi), z);
  };
  std::vector<cl_float4> wo, wi;
  for (int k = 0; k < 20000; ++k) {
    wo.push_back(hemisphere());
    wi.push_back(hemisphere());
  }
  for (float alpha : {1e-3f, 0.05f, 0.2f, 0.5f, 1.0f}) {
    const auto pair = ggx_eval(alpha, wo, wi);
    const auto in = ggx_eval(alpha, wi, wi);
    for (size_t k = 0; k < wo.size(); ++k) {
      const double g1o = pair[k].g1, g1i = in[k].g1, g2 = pair[k].g2;
      ASSERT_TRUE(std::isfinite(g2)) << "alpha " << alpha;
      ASSERT_LE(g2, std::min(g1o, g1i) + 1e-6) << "alpha " << alpha << " k " << k;
      ASSERT_GE(g2, g1o * g1i - 1e-6) << "alpha " << alpha << " k " << k;
    }
  }
}

// Everything stays finite at grazing angles (w.z = 1e-7, and 0) with the
// smallest supported alpha.
TEST(Ggx, FiniteAtGrazingAnglesAndTinyAlpha) {
  const std::vector<dvec3> dirs = {dvec3(1.0, 0.0, 1e-7), dvec3(0.6, 0.8, 1e-7), dvec3(1.0, 0.0, 0.0),
                                   dvec3(0.0, 0.0, 1.0), direction_at(60.0), dvec3(-1.0, 0.0, 1e-7)};
  std::vector<cl_float4> wo, wi;
  for (const dvec3& a : dirs)
    for (const dvec3& b : dirs) {
      wo.push_back(f4(glm::normalize(a)));
      wi.push_back(f4(glm::normalize(b)));
    }
  for (float alpha : {1e-3f, 0.01f, 1.0f}) {
    const auto out = ggx_eval(alpha, wo, wi);
    for (size_t k = 0; k < out.size(); ++k) {
      SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " wo " << wo[k].s[0] << "," << wo[k].s[1] << ","
                                        << wo[k].s[2] << " wi " << wi[k].s[0] << "," << wi[k].s[1] << ","
                                        << wi[k].s[2]);
      for (double v : {out[k].d, out[k].g1, out[k].g2, out[k].pdf}) {
        EXPECT_TRUE(std::isfinite(v)) << v;
        EXPECT_GE(v, 0.0);
      }
    }
  }
}

// --------------------------------------------------------------- the frame

// The polynomial sine, cosine and atan2 the light samplers use instead of
// PoCL's (lib/sampling.h), against double precision over their ranges.
TEST(Sampling, PolynomialTrigonometryIsWithinAFewUlp) {
  double worst_sin = 0.0, worst_atan = 0.0;
  for (int i = 0; i <= 200000; ++i) {
    const float a = float(2.0 * kPi * i / 200000.0);
    float c;
    const float s = sin_cos_full_turn(a, &c);
    worst_sin = std::max({worst_sin, std::abs(s - std::sin(double(a))), std::abs(c - std::cos(double(a)))});
  }
  for (int i = 0; i <= 2000; ++i)
    for (int j = -1000; j <= 1000; ++j) {
      const float y = float(i) * 1e-3f, x = float(j) * 1.3e-3f;
      if (y == 0.0f && x == 0.0f) continue;
      worst_atan = std::max(worst_atan, std::abs(atan2_upper(y, x) - std::atan2(double(y), double(x))));
    }
  EXPECT_LT(worst_sin, 6e-7) << "sin_cos_full_turn";
  EXPECT_LT(worst_atan, 6e-7) << "atan2_upper";  // a few ulp of pi
  EXPECT_EQ(atan2_upper(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(atan2_upper(0.0f, -1.0f), kPi, 3e-7);
  EXPECT_NEAR(atan2_upper(1e-30f, 1.0f), 1e-30f, 1e-36f);
  EXPECT_NEAR(atan2_upper(1e30f, 1.0f), kPi / 2, 3e-7);
}

TEST(Sampling, FrameFromNormalIsOrthonormalAndRightHanded) {
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss;
  std::vector<cl_float4> n = {f4(0, 0, -1), f4(0, 0, 1), f4(glm::normalize(dvec3(1e-4, 0, -1))),
                              f4(glm::normalize(dvec3(0, 1e-3, -1))), f4(glm::normalize(dvec3(3e-4, -2e-4, -1))),
                              f4(glm::normalize(dvec3(1e-20, 1e-20, -1))), f4(1, 0, 0), f4(0, -1, 0),
                              f4(0, 1, -0.0)};
  while (n.size() < 100000) {
    const dvec3 v(gauss(rng), gauss(rng), gauss(rng));
    if (glm::length(v) > 1e-6) n.push_back(f4(glm::normalize(v)));
  }
  // Normals crowding -z, where the frame's branch-free formula divides by
  // (1 + |n.z|) ... and where Frisvad's original one failed.
  for (int k = 0; k < 1000; ++k) {
    const double e = std::pow(10.0, -1.0 - 7.0 * k / 1000.0), phi = 0.1 * k;
    n.push_back(f4(glm::normalize(dvec3(e * std::cos(phi), e * std::sin(phi), -1.0))));
  }
  std::vector<cl_float4> ts, bs;
  for (const cl_float4& v : n) {
    float3 t, b;
    frame_from_normal(xyz(v), &t, &b);
    ts.push_back(f4(t));
    bs.push_back(f4(b));
  }
  for (size_t i = 0; i < n.size(); ++i) {
    const dvec3 nn = d3(n[i]), t = d3(ts[i]), b = d3(bs[i]);
    SCOPED_TRACE(::testing::Message() << "n " << nn.x << "," << nn.y << "," << nn.z);
    ASSERT_NEAR(glm::length(t), 1.0, 1e-5);
    ASSERT_NEAR(glm::length(b), 1.0, 1e-5);
    ASSERT_NEAR(glm::dot(t, b), 0.0, 1e-5);
    ASSERT_NEAR(glm::dot(t, nn), 0.0, 1e-5);
    ASSERT_NEAR(glm::dot(b, nn), 0.0, 1e-5);
    ASSERT_LT(glm::length(glm::cross(t, b) - nn), 1e-5);
  }
}

// ---------------------------------------------------------- finite corners

TEST(Sampling, EveryWarpIsFiniteAtTheCornersOfTheSquare) {
  const float corners[] = {0.0f, 0.5f, 1.0f - 0x1p-24f};
  std::vector<cl_float2> u;
  for (float a : corners)
    for (float b : corners) u.push_back({{a, b}});
  std::vector<std::pair<std::string, WarpParams>> warps = {
      {"cosine", {kCosine}}, {"sphere", {kSphere}}, {"disk", {kDisk}}, {"triangle", {kTriangle}},
      {"rectangle", {kRectangle, 0.0f, f4(0.3, -1.2, 2.0), f4(2.0, 0.5, 0.3), f4(-0.4, 1.5, 0.8)}}};
  for (float c : {1e-7f, 1e-3f, 0.1f, 1.0f, 2.0f}) warps.push_back({"cone " + std::to_string(c), {kCone, c}});
  for (float alpha : {1e-3f, 0.05f, 1.0f})
    for (const dvec3& wo : {dvec3(0, 0, 1), direction_at(60.0), glm::normalize(dvec3(1.0, 0.0, 1e-7))})
      warps.push_back({"ggx alpha " + std::to_string(alpha) + " wo.z " + std::to_string(wo.z),
                       {kGgxVndf, alpha, f4(wo)}});
  for (const auto& [name, w] : warps) {
    const auto out = sample_at(w, u);
    const bool direction = w.mode == kCosine || w.mode == kSphere || w.mode == kCone || w.mode == kGgxVndf;
    for (size_t i = 0; i < u.size(); ++i) {
      SCOPED_TRACE(::testing::Message() << name << " u " << u[i].s[0] << "," << u[i].s[1]);
      for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(out[i].s[c])) << out[i].s[c];
      if (direction) EXPECT_NEAR(glm::length(d3(out[i])), 1.0, 1e-5);
      if (w.mode == kDisk) EXPECT_LE(glm::length(d3(out[i])), 1.0 + 1e-6);
      if (w.mode == kTriangle) {
        EXPECT_GE(out[i].s[0], 0.0f);
        EXPECT_GE(out[i].s[1], 0.0f);
        EXPECT_LE(out[i].s[0] + out[i].s[1], 1.0f);
      }
    }
    if (w.mode == kGgxVndf || w.mode == kCosine) {  // the density at the samples is finite too
      const auto pdf = library_pdf(w, out);
      for (size_t i = 0; i < pdf.size(); ++i) EXPECT_TRUE(std::isfinite(pdf[i])) << name << " " << i;
    }
  }
}

}  // namespace
}  // namespace caustica
