// Host tests of next-event estimation toward planar lights (issue 39):
// rectangles and triangles sampled by the solid angle they subtend
// (lib/spherical_sampling.h: spherical rectangles and spherical triangles)
// where it is large, by area elsewhere (lights/rect_light.h,
// lights/triangle_light.h), the kernels' own source compiled as C++.
//
// - Chi-square: the directions sample_light draws from a point against
//   light_pdf, the density MIS reads, in the chi-square harness of
//   tests/host/test_sampling.cpp. The parametrisation is the light's own
//   surface ((s, t) of a rectangle; Duffy's square of a triangle, b1 = x1 (1 -
//   x2), b2 = x1 x2), so a light of any size is resolved by the same cells;
//   the measure per unit (x1, x2) is the surface's times cos_l / d^2.
//   Points near, oblique, almost in the plane and far (the area branch),
//   and a parallelogram (area always), so both branches and the switch
//   between them are tested.
// - Energy: the mean of L cos / pdf over the samples is the irradiance,
//   which Lambert's formula for a polygon gives exactly; solid-angle and
//   area sampling must both reach it, and near a large light the
//   solid-angle estimate must have the smaller variance (the reason to
//   have it).
// - Spheres sample the cone they subtend (lights/sphere_light.h): the same
//   chi-square in the cone's own parametrisation, and the irradiance of a
//   receiver facing the centre, pi L (r / d)^2, by cone and by area.
// - Robustness: u at the corners of the square, points on the light's
//   plane and on its edges give a finite sample or none, never NaN.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

// The solid-angle samplers from 0.01 sr on (the built-in switch is 0.1 sr,
// chosen for speed), so that the small and oblique lights below test them
// as well.
#define LIGHT_SPHERICAL_MIN_SOLID_ANGLE 1e-2f
#include "lib/lights.h"
#include "lib/rng.h"
#include "tests/support/chi_square.h"

namespace caustica {
namespace {

using glm::dvec3;
using test::ChiSquare;
using test::Domain;

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kSamples = 1000000;
const float kNoEnvironment[1] = {0.0f};

float4 f4(const dvec3& v, double w = 0.0) {
  return make_float4_xyz(make_float3(float(v.x), float(v.y), float(v.z)), float(w));
}
dvec3 d3(float3 v) { return dvec3(v.x, v.y, v.z); }
dvec3 d3(const cl_float4& v) { return dvec3(v.s[0], v.s[1], v.s[2]); }
float3 f3(const dvec3& v) { return make_float3(float(v.x), float(v.y), float(v.z)); }
cl_float4 cl4(const dvec3& v) {
  return {{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), 0.0f}};
}

// A planar light as the tests see it: its Light and its vertices.
struct Planar {
  Light light{};
  std::vector<dvec3> vertices;  // counter-clockwise seen from the emitting side
  bool rectangle = false;
  dvec3 normal() const { return glm::normalize(glm::cross(vertices[1] - vertices[0], vertices[2] - vertices[0])); }
  double area() const { return light.emitted.w; }
};

Planar rect(const dvec3& centre, const dvec3& eu, const dvec3& ev) {
  Planar p;
  p.rectangle = true;
  p.light.kind = LIGHT_RECT;
  p.light.p0 = f4(centre);
  p.light.p1 = f4(eu);
  p.light.p2 = f4(ev);
  p.light.emitted = f4(dvec3(1.0), glm::length(glm::cross(eu, ev)));
  p.light.select_probability = p.light.select_cdf = 1.0f;
  const dvec3 c = centre - 0.5 * (eu + ev);
  p.vertices = {c, c + eu, c + eu + ev, c + ev};
  return p;
}

Planar triangle(const dvec3& v0, const dvec3& v1, const dvec3& v2) {
  Planar p;
  p.light.kind = LIGHT_TRIANGLE;
  p.light.p0 = f4(v0);
  p.light.p1 = f4(v1);
  p.light.p2 = f4(v2);
  p.light.emitted = f4(dvec3(1.0), 0.5 * glm::length(glm::cross(v1 - v0, v2 - v0)));
  p.light.select_probability = p.light.select_cdf = 1.0f;
  p.vertices = {v0, v1, v2};
  return p;
}

// The light's surface point at unit coordinates (x1, x2), and the area per
// unit of x1 x2 there.
dvec3 surface_at(const Planar& l, double x1, double x2, double* area_jacobian) {
  const std::vector<dvec3>& v = l.vertices;
  if (l.rectangle) {
    *area_jacobian = l.area();
    return v[0] + x1 * (v[1] - v[0]) + x2 * (v[3] - v[0]);
  }
  *area_jacobian = 2.0 * l.area() * x1;  // Duffy: d(b1, b2) = x1 d(x1, x2)
  return v[0] + x1 * (1.0 - x2) * (v[1] - v[0]) + x1 * x2 * (v[2] - v[0]);
}

// Where the ray from p along w meets the light's plane; false when it does not.
bool plane_point(const Planar& l, const dvec3& p, const dvec3& w, dvec3* q) {
  const dvec3 n = l.normal();
  const double den = glm::dot(w, n);
  if (den == 0.0) return false;
  const double t = glm::dot(l.vertices[0] - p, n) / den;
  if (!(t > 0.0)) return false;
  *q = p + t * w;
  return true;
}

Domain light_domain(const Planar& l, const dvec3& p) {
  Domain d{32, 32, {}, {}};
  d.to_unit = [l, p](const cl_float4& s, double* x1, double* x2) {
    dvec3 q;
    if (!plane_point(l, p, glm::normalize(d3(s)), &q)) return false;
    const std::vector<dvec3>& v = l.vertices;
    const dvec3 e1 = v[1] - v[0], e2 = (l.rectangle ? v[3] : v[2]) - v[0], r = q - v[0];
    // (a, b) with r = a e1 + b e2, by least squares (exact on the plane).
    const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2);
    const double r1 = glm::dot(r, e1), r2 = glm::dot(r, e2), det = g11 * g22 - g12 * g12;
    const double a = (g22 * r1 - g12 * r2) / det, b = (g11 * r2 - g12 * r1) / det;
    const double slack = 1e-4;
    if (l.rectangle) {
      if (a < -slack || a > 1.0 + slack || b < -slack || b > 1.0 + slack) return false;
      *x1 = std::clamp(a, 0.0, 1.0);
      *x2 = std::clamp(b, 0.0, 1.0);
      return true;
    }
    if (a < -slack || b < -slack || a + b > 1.0 + slack) return false;
    const double sum = std::max(a + b, 0.0);
    *x1 = std::clamp(sum, 0.0, 1.0);
    *x2 = sum > 0.0 ? std::clamp(b / sum, 0.0, 1.0) : 0.5;
    return true;
  };
  d.from_unit = [l, p](double x1, double x2, double* jacobian) {
    double area_jacobian;
    const dvec3 q = surface_at(l, x1, x2, &area_jacobian);
    const dvec3 to_q = q - p;
    const double d2 = glm::dot(to_q, to_q);
    const dvec3 w = to_q / std::sqrt(d2);
    *jacobian = area_jacobian * std::abs(glm::dot(w, l.normal())) / d2;  // solid angle per unit x1 x2
    return cl4(w);
  };
  return d;
}

// sample_light's directions from p (none: the zero vector, outside).
std::vector<cl_float4> sample_directions(const Planar& l, const dvec3& p, cl_uint key, size_t n) {
  std::vector<cl_float4> out;
  out.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    LightSample s;
    const float2 u = make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u));
    out.push_back(sample_light(&l.light, kNoEnvironment, 1.0f, f3(p), u, &s) ? cl4(d3(s.wi)) : cl4(dvec3(0.0)));
  }
  return out;
}

// light_pdf, the density MIS reads, at each direction (at the plane's point).
test::Density library_density(const Planar& l, const dvec3& p) {
  return [l, p](const std::vector<cl_float4>& dirs) {
    std::vector<double> out;
    for (const cl_float4& s : dirs) {
      const dvec3 w = glm::normalize(d3(s));
      dvec3 q;
      out.push_back(plane_point(l, p, w, &q) ? light_pdf(&l.light, kNoEnvironment, 1.0f, f3(p), f3(q), f3(w)) : 0.0);
    }
    return out;
  };
}

// Lambert: the irradiance at p (normal n) from a polygon of unit radiance,
// 1/2 sum over edges of the edge's angle times the cosine of its plane's
// normal with n.
double lambert_irradiance(const Planar& l, const dvec3& p, const dvec3& n) {
  double e = 0.0;
  const size_t k = l.vertices.size();
  for (size_t i = 0; i < k; ++i) {
    const dvec3 a = glm::normalize(l.vertices[i] - p), b = glm::normalize(l.vertices[(i + 1) % k] - p);
    e += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(glm::normalize(glm::cross(a, b)), n);
  }
  return 0.5 * std::abs(e);
}

struct Estimate {
  double mean = 0.0, variance = 0.0;
};

// The irradiance estimate L cos / pdf of the light's own sampler, or of the
// area sampler forced (area = true).
Estimate irradiance_estimate(const Planar& l, const dvec3& p, const dvec3& n, bool area, cl_uint key) {
  double sum = 0.0, sum2 = 0.0;
  for (uint32_t i = 0; i < kSamples; ++i) {
    const float2 u = make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u));
    LightSample s;
    bool ok;
    if (area) {
      float3 p_error, n_l;
      const float3 q = l.rectangle ? rect_light_emission_point(&l.light, u, &p_error, &n_l)
                                   : triangle_light_emission_point(&l.light, u, &p_error, &n_l);
      ok = sample_area_light_point(&l.light, f3(p), q, p_error, n_l, &s);
    } else {
      ok = sample_light(&l.light, kNoEnvironment, 1.0f, f3(p), u, &s);
    }
    const double x = ok ? std::max(0.0, glm::dot(d3(s.wi), n)) * s.radiance.x / s.pdf : 0.0;
    sum += x;
    sum2 += x * x;
  }
  Estimate e;
  e.mean = sum / kSamples;
  e.variance = std::max(0.0, sum2 / kSamples - e.mean * e.mean);
  return e;
}

bool by_solid_angle(const Planar& l, const dvec3& p) {
  SphericalRectangle r;
  SphericalTriangle t;
  return l.rectangle ? rect_light_by_solid_angle(&l.light, f3(p), rect_light_normal(&l.light), &r)
                     : triangle_light_by_solid_angle(&l.light, f3(p), triangle_light_normal(&l.light), &t);
}

struct Case {
  std::string name;
  Planar light;
  dvec3 p;
  bool solid_angle;  // which branch the point must take
};

// A unit square 1 above the origin facing down, and a rotated triangle of
// similar size, seen from points near, oblique, close to the plane, far.
std::vector<Case> cases() {
  const dvec3 down_u(1.0, 0.0, 0.0), down_v(0.0, -1.0, 0.0);  // cross(u, v) = -z: faces down
  const Planar square = rect(dvec3(0.0, 0.0, 1.0), down_u, down_v);
  const Planar tilted = rect(dvec3(0.3, -0.2, 1.5), dvec3(0.8, 0.0, 0.6), dvec3(0.0, -1.5, 0.0));
  const Planar parallelogram = rect(dvec3(0.0, 0.0, 1.0), dvec3(1.0, 0.0, 0.0), dvec3(0.4, -1.0, 0.0));
  const Planar tri = triangle(dvec3(-0.6, -0.5, 1.0), dvec3(0.2, 0.9, 1.2), dvec3(0.7, -0.4, 0.8));
  return {
      {"square above", square, dvec3(0.1, 0.2, 0.0), true},
      {"square oblique", square, dvec3(1.8, -0.7, 0.7), true},
      {"square close to its plane", square, dvec3(0.2, -0.1, 0.97), true},
      {"square far", square, dvec3(3.0, 2.0, -15.0), false},
      {"tilted rectangle", tilted, dvec3(-0.5, 0.3, 0.2), true},
      {"parallelogram", parallelogram, dvec3(0.1, 0.0, 0.0), false},
      {"triangle above", tri, dvec3(0.0, 0.0, 0.0), true},
      {"triangle oblique", tri, dvec3(2.0, 1.0, 0.6), true},
      {"triangle close to its plane", tri, dvec3(0.05, -0.02, 0.97), true},
      {"triangle far", tri, dvec3(-2.0, 4.0, -20.0), false},
  };
}

TEST(LightSamplingChiSquare, PlanarLightsFromNearAndFar) {
  const std::vector<Case> all = cases();
  cl_uint key = 700;
  for (const Case& c : all) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(by_solid_angle(c.light, c.p), c.solid_angle);
    const ChiSquare r =
        test::chi_square_test(sample_directions(c.light, c.p, key++, kSamples), light_domain(c.light, c.p),
                              library_density(c.light, c.p));
    std::cout << c.name << ": " << r.describe() << "\n";
    EXPECT_EQ(r.outside, 0u) << r.describe();
    EXPECT_NEAR(r.integral, 1.0, 1e-3) << r.describe();
    EXPECT_GT(r.p, test::sidak(static_cast<int>(all.size()))) << r.describe();
  }
}

TEST(LightSampling, IrradianceMatchesLambertByAreaAndBySolidAngle) {
  cl_uint key = 800;
  for (const Case& c : cases()) {
    if (!c.solid_angle) continue;
    SCOPED_TRACE(c.name);
    // The receiver faces the light (all of which is above its horizon in
    // every case, as Lambert's formula needs).
    const dvec3 n = -c.light.normal();
    const double exact = lambert_irradiance(c.light, c.p, n);
    const Estimate spherical = irradiance_estimate(c.light, c.p, n, false, key++);
    const Estimate area = irradiance_estimate(c.light, c.p, n, true, key++);
    const double se_spherical = std::sqrt(spherical.variance / kSamples), se_area = std::sqrt(area.variance / kSamples);
    std::cout << c.name << ": exact " << exact << ", by solid angle " << spherical.mean << " +- " << se_spherical
              << ", by area " << area.mean << " +- " << se_area << " (variance ratio "
              << spherical.variance / area.variance << ")\n";
    EXPECT_NEAR(spherical.mean, exact, 5.0 * se_spherical + 1e-5 * exact);
    EXPECT_NEAR(area.mean, exact, 5.0 * se_area + 1e-5 * exact);
    EXPECT_LT(spherical.variance, area.variance);
  }
}

TEST(LightSampling, PlanarSamplesAreFiniteAtTheCornersAndOnThePlane) {
  const float edges[] = {0.0f, 1e-7f, 0.5f, 1.0f - 1e-7f, 0x1.fffffep-1f};
  std::vector<Case> all = cases();
  // Points on the plane: inside, on an edge, on a vertex, outside.
  const Planar square = all[0].light, tri = all[6].light;
  for (const dvec3& p : {dvec3(0.1, 0.2, 1.0), dvec3(0.5, 0.0, 1.0), dvec3(0.5, -0.5, 1.0), dvec3(3.0, 0.0, 1.0)})
    all.push_back({"on the square's plane", square, p, false});
  all.push_back({"on the triangle's vertex", tri, tri.vertices[1], false});
  all.push_back({"at 1e-6 below the square", square, dvec3(0.1, 0.2, 1.0 - 1e-6), false});
  for (const Case& c : all) {
    SCOPED_TRACE(c.name);
    for (float ux : edges)
      for (float uy : edges) {
        LightSample s;
        if (!sample_light(&c.light.light, kNoEnvironment, 1.0f, f3(c.p), make_float2(ux, uy), &s)) continue;
        EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.0f) << ux << " " << uy;
        EXPECT_TRUE(std::isfinite(s.wi.x + s.wi.y + s.wi.z + s.point.x + s.point.y + s.point.z)) << ux << " " << uy;
        EXPECT_NEAR(glm::length(d3(s.wi)), 1.0, 1e-5);
        // The point lies on the light: in its plane, within its bounds.
        const double off_plane = std::abs(glm::dot(d3(s.point) - c.light.vertices[0], c.light.normal()));
        EXPECT_LT(off_plane, 1e-5) << ux << " " << uy;
        const float pdf = light_pdf(&c.light.light, kNoEnvironment, 1.0f, f3(c.p), s.point, s.wi);
        EXPECT_NEAR(pdf, s.pdf, 1e-4f * s.pdf) << "sample and MIS density disagree at " << ux << " " << uy;
      }
  }
}

// ------------------------------------------------------------ sphere lights

Light sphere_light(const dvec3& centre, double radius) {
  Light l{};
  l.kind = LIGHT_SPHERE;
  l.p0 = f4(centre, radius);
  l.emitted = f4(dvec3(1.0), 4.0 * kPi * radius * radius);
  l.select_probability = l.select_cdf = 1.0f;
  return l;
}

// ((1 - cos theta) / one_minus_cos_max, phi) of the cone around `axis`.
Domain cone_domain_around(const dvec3& axis, double one_minus_cos_max) {
  float3 t3, b3;
  frame_from_normal(f3(axis), &t3, &b3);
  const dvec3 t = d3(t3), b = d3(b3);
  Domain d{32, 64, {}, {}};
  d.to_unit = [=](const cl_float4& s, double* x1, double* x2) {
    const dvec3 v = glm::normalize(d3(s));
    const double z = glm::dot(v, axis), x = glm::dot(v, t), y = glm::dot(v, b);
    if (z <= 0.0) return false;
    const double u = ((x * x + y * y) / (1.0 + z)) / one_minus_cos_max;
    if (u > 1.0 + 1e-4) return false;
    *x1 = std::min(u, 1.0);
    *x2 = test::wrap_unit_angle(x, y);
    return true;
  };
  d.from_unit = [=](double x1, double x2, double* jacobian) {
    const double omc = x1 * one_minus_cos_max, s = std::sqrt(omc * (2.0 - omc)), phi = 2.0 * kPi * x2;
    *jacobian = 2.0 * kPi * one_minus_cos_max;
    return cl4(s * std::cos(phi) * t + s * std::sin(phi) * b + (1.0 - omc) * axis);
  };
  return d;
}

// The cone a sphere subtends, sampled from near, middling and far points;
// the irradiance of a receiver facing its centre is pi L (r / d)^2 exactly,
// which sampling by area (uniform over the sphere, the far side rejected)
// reaches too, with a larger variance.
TEST(LightSampling, SphereConeFitsAndMatchesItsIrradiance) {
  const dvec3 centre(0.3, 1.0, -0.2);
  const double radius = 0.5;
  const Light l = sphere_light(centre, radius);
  const double distances[] = {0.55, 1.5, 40.0};
  cl_uint key = 950;
  for (double dist : distances) {
    SCOPED_TRACE(dist);
    const dvec3 axis = glm::normalize(dvec3(0.2, -1.0, 0.4));
    const dvec3 p = centre - dist * axis;
    const double sin2 = radius * radius / (dist * dist), omc = sin2 / (1.0 + std::sqrt(1.0 - sin2));
    std::vector<cl_float4> dirs;
    for (uint32_t i = 0; i < kSamples; ++i) {
      LightSample s;
      const float2 u = make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u));
      dirs.push_back(sample_light(&l, kNoEnvironment, 1.0f, f3(p), u, &s) ? cl4(d3(s.wi)) : cl4(dvec3(0.0)));
    }
    ++key;
    const ChiSquare r = test::chi_square_test(dirs, cone_domain_around(axis, omc), [&](const std::vector<cl_float4>& w) {
      std::vector<double> out;
      for (const cl_float4& v : w) out.push_back(light_pdf(&l, kNoEnvironment, 1.0f, f3(p), f3(p), f3(d3(v))));
      return out;
    });
    std::cout << "sphere at distance " << dist << ": " << r.describe() << "\n";
    EXPECT_EQ(r.outside, 0u) << r.describe();
    EXPECT_NEAR(r.integral, 1.0, 1e-3) << r.describe();
    EXPECT_GT(r.p, test::sidak(3)) << r.describe();

    const double exact = kPi * sin2;
    double sum = 0.0, sum2 = 0.0, area_sum = 0.0, area_sum2 = 0.0;
    for (uint32_t i = 0; i < kSamples; ++i) {
      const float2 u = make_float2(random_float(key, 2u * i), random_float(key, 2u * i + 1u));
      LightSample s;
      double x = sample_light(&l, kNoEnvironment, 1.0f, f3(p), u, &s)
                     ? std::max(0.0, glm::dot(d3(s.wi), axis)) * s.radiance.x / s.pdf
                     : 0.0;
      sum += x;
      sum2 += x * x;
      float3 p_error, n_l;
      const float3 q = sphere_light_emission_point(&l, u, &p_error, &n_l);
      x = sample_area_light_point(&l, f3(p), q, p_error, n_l, &s) ? std::max(0.0, glm::dot(d3(s.wi), axis)) / s.pdf
                                                                   : 0.0;
      area_sum += x;
      area_sum2 += x * x;
    }
    ++key;
    const double mean = sum / kSamples, var = sum2 / kSamples - mean * mean;
    const double area_mean = area_sum / kSamples, area_var = area_sum2 / kSamples - area_mean * area_mean;
    std::cout << "  irradiance exact " << exact << ", by cone " << mean << ", by area " << area_mean
              << " (variance ratio " << var / area_var << ")\n";
    EXPECT_NEAR(mean, exact, 5.0 * std::sqrt(var / kSamples) + 1e-5 * exact);
    EXPECT_NEAR(area_mean, exact, 5.0 * std::sqrt(area_var / kSamples) + 1e-5 * exact);
    EXPECT_LT(var, area_var);
  }
}

}  // namespace
}  // namespace caustica
