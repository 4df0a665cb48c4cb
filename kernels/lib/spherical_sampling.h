#line 2 "kernels/lib/spherical_sampling.h"
/* Directions uniform over the solid angle a planar light subtends: the
 * spherical rectangle (Urena, Fajardo and King 2013, as Cycles samples its
 * area lights) and the spherical triangle (Arvo 1995, as pbrt-v4 samples
 * its triangles). Both return the point on the light that the direction
 * reaches, so the shadow ray aims at a point of the light's own surface as
 * the area samplers' do, and the density is 1 / solid angle.
 *
 * Rules: float32 throughout; the solid angle is a sum of angles minus a
 * multiple of pi, which cancels for a small light (a few 1e-7 absolute),
 * so callers use these only above LIGHT_SPHERICAL_MIN_SOLID_ANGLE, where
 * that error is below 1e-4 relative, and sample by area below it (where
 * 1/d^2 and the cosine vary little over the light, so area sampling loses
 * nothing). The decision is a function of the shading point and the light
 * alone, so the sampler and the MIS density (light_pdf) always agree. Every
 * input of u in [0, 1)^2 gives a finite point on the light (clamped to it);
 * set-ups that cannot hold (the point in the light's plane) say so. */
#ifndef CAUSTICA_LIB_SPHERICAL_SAMPLING_H
#define CAUSTICA_LIB_SPHERICAL_SAMPLING_H

#include "lib/geometry.h"
#include "lib/sampling.h"

/* Below this estimated solid angle (steradians) planar lights are sampled
 * by area: chosen by measurement (docs/performance.md, "Light sampling by
 * solid angle"). */
#ifndef LIGHT_SPHERICAL_MIN_SOLID_ANGLE
#define LIGHT_SPHERICAL_MIN_SOLID_ANGLE 1e-2f
#endif
/* Above this solid angle (a point almost on the light, which then covers
 * nearly a hemisphere) the triangle's angles lose their accuracy (pbrt-v4's
 * limit): area sampling again. */
#define LIGHT_SPHERICAL_MAX_SOLID_ANGLE 6.22f

/* The solid angle of a planar light of the given area, unit normal n and
 * centre c seen from p, to first order (area cos / d^2): the cheap test
 * that decides between the two samplers. */
inline float planar_light_solid_angle_estimate(float3 p, float3 c, float3 n, float area) {
  const float3 d = c - p;
  const float d2 = dot(d, d);
  return area * fabs(dot(d, n)) / (d2 * sqrt(d2));
}

/* The angle between unit vectors, accurate near 0 and pi (acos is not). */
inline float angle_between_unit(float3 a, float3 b) {
  if (dot(a, b) < 0.0f) return M_PI_F - 2.0f * asin(fmin(1.0f, 0.5f * length(a + b)));
  return 2.0f * asin(fmin(1.0f, 0.5f * length(b - a)));
}

/* A rectangle corner + s edge_x + t edge_y (s, t in [0, 1], the edges
 * orthogonal) seen from o, in the frame of its edges: x, y the unit edge
 * directions, z their normal turned away from the rectangle (so that the
 * rectangle lies at z = z0 < 0), the rectangle spanning [x0, x1] x [y0, y1]. */
typedef struct {
  float3 o, x, y, z;
  float x0, x1, y0, y1, z0;
  float b0, b1, k; /* the angles the sampler inverts (the paper's names) */
  float solid_angle;
} SphericalRectangle;

/* False when o lies in the rectangle's plane (no solid angle) or the set-up
 * does not hold numerically. */
inline bool spherical_rectangle_setup(float3 o, float3 corner, float3 edge_x, float3 edge_y, SphericalRectangle* r) {
  const float len_x = length(edge_x), len_y = length(edge_y);
  r->o = o;
  r->x = edge_x / len_x;
  r->y = edge_y / len_y;
  r->z = cross(r->x, r->y);
  const float3 d = corner - o;
  r->z0 = dot(d, r->z);
  if (r->z0 > 0.0f) {
    r->z = -r->z;
    r->z0 = -r->z0;
  }
  r->x0 = dot(d, r->x);
  r->y0 = dot(d, r->y);
  r->x1 = r->x0 + len_x;
  r->y1 = r->y0 + len_y;
  const float z0 = r->z0, z2 = z0 * z0;
  if (!(z0 < 0.0f)) return false;
  /* The inner angles between the planes through o and consecutive edges,
   * from their normals n0 = (0, z0, -y0), n1 = (-z0, 0, x1),
   * n2 = (0, -z0, y1), n3 = (z0, 0, -x0), each normalised. */
  const float l0 = sqrt(z2 + r->y0 * r->y0), l1 = sqrt(z2 + r->x1 * r->x1);
  const float l2 = sqrt(z2 + r->y1 * r->y1), l3 = sqrt(z2 + r->x0 * r->x0);
  const float g0 = acos(clamp(r->y0 * r->x1 / (l0 * l1), -1.0f, 1.0f));
  const float g1 = acos(clamp(-r->x1 * r->y1 / (l1 * l2), -1.0f, 1.0f));
  const float g2 = acos(clamp(r->y1 * r->x0 / (l2 * l3), -1.0f, 1.0f));
  const float g3 = acos(clamp(-r->x0 * r->y0 / (l3 * l0), -1.0f, 1.0f));
  r->b0 = -r->y0 / l0; /* n0.z */
  r->b1 = r->y1 / l2;  /* n2.z */
  r->k = 2.0f * M_PI_F - g2 - g3;
  r->solid_angle = g0 + g1 - r->k;
  return r->solid_angle > 0.0f && isfinite(r->solid_angle);
}

/* The point of the rectangle in direction of the sample u (density
 * 1 / solid_angle over directions); *p_error bounds its error. */
inline float3 spherical_rectangle_sample(const SphericalRectangle* r, float2 u, float3* p_error) {
  /* The x at which the solid angle left of x is u.x of the whole. */
  const float au = u.x * r->solid_angle + r->k;
  float cos_au;
  const float sin_au = sincos(au, &cos_au);
  const float fu_num = cos_au * r->b0 - r->b1;
  const float cu_den = sqrt(fu_num * fu_num + r->b0 * r->b0 * sin_au * sin_au);
  const float cu = clamp(cu_den > 0.0f ? copysign(1.0f, fu_num) * sin_au / cu_den : 0.0f, -1.0f, 1.0f);
  const float xu = clamp(-(cu * r->z0) / fmax(sqrt(fmax(0.0f, 1.0f - cu * cu)), 1e-30f), r->x0, r->x1);
  /* The y at which the solid angle below y, along that x, is u.y of it. */
  const float dist = sqrt(xu * xu + r->z0 * r->z0);
  const float h0 = r->y0 / sqrt(dist * dist + r->y0 * r->y0);
  const float h1 = r->y1 / sqrt(dist * dist + r->y1 * r->y1);
  const float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
  const float yv = clamp(hv2 < 1.0f - 1e-6f ? hv * dist / sqrt(1.0f - hv2) : r->y1, r->y0, r->y1);
  /* o plus three terms along unit vectors, each a few roundings of its
   * size; the plane itself is known to a few roundings of |o| and the
   * distance to it. */
  *p_error = error_gamma(16.0f) * (fabs(r->o) + splat_float3(fabs(xu) + fabs(yv) + fabs(r->z0)));
  return r->o + xu * r->x + yv * r->y + r->z0 * r->z;
}

/* A spherical triangle: the unit directions from p to the vertices and its
 * inner angle alpha at a; false when p lies in the triangle's plane (or on
 * an edge's line) or the set-up does not hold numerically. */
typedef struct {
  float3 a, b, c;
  float alpha, solid_angle;
} SphericalTriangle;

inline bool spherical_triangle_setup(float3 p, float3 v0, float3 v1, float3 v2, SphericalTriangle* s) {
  s->a = normalize(v0 - p);
  s->b = normalize(v1 - p);
  s->c = normalize(v2 - p);
  float3 n_ab = cross(s->a, s->b), n_bc = cross(s->b, s->c), n_ca = cross(s->c, s->a);
  const float l_ab = length(n_ab), l_bc = length(n_bc), l_ca = length(n_ca);
  if (!(l_ab > 0.0f && l_bc > 0.0f && l_ca > 0.0f)) return false;
  n_ab /= l_ab;
  n_bc /= l_bc;
  n_ca /= l_ca;
  s->alpha = angle_between_unit(n_ab, -n_ca);
  const float beta = angle_between_unit(n_bc, -n_ab), gamma = angle_between_unit(n_ca, -n_bc);
  s->solid_angle = s->alpha + beta + gamma - M_PI_F;
  return s->solid_angle > 0.0f && isfinite(s->solid_angle);
}

/* The unit component of v orthogonal to the unit vector w. */
inline float3 orthogonal_unit(float3 v, float3 w) {
  const float3 o = v - dot(v, w) * w;
  const float l = length(o);
  return l > 0.0f ? o / l : splat_float3(0.0f);
}

/* A direction uniform over the spherical triangle (density 1 / solid
 * angle): the sub-triangle a, b, c' of area u.x times the whole fixes c' on
 * the arc from a to c, then u.y places the direction on the arc from b to
 * c' (uniformly in 1 - cos of the angle from b). */
inline float3 spherical_triangle_sample(const SphericalTriangle* s, float2 u) {
  const float area = u.x * s->solid_angle;
  /* Arvo's cos(b') (the angle at a from b to c') would be 1 minus a few
   * 1e-6 for a sliver of the triangle next to a (small u.x), where float
   * keeps only a percent of it; 1 - cos(b') instead, rewritten without a
   * difference of nearly equal terms (phi = area - alpha, the paper's s
   * and t its sine and cosine):
   *   1 - cos b' = 2 sin^2(area / 2) (1 + cos c) / (k2 sin phi + k1 cos phi),
   *   k1 = cos phi - cos alpha = -2 sin(area / 2) sin(area / 2 - alpha),
   *   k2 = sin phi + sin alpha cos c. */
  float cos_phi;
  const float sin_phi = sincos(area - s->alpha, &cos_phi);
  const float half_sin = sin(0.5f * area);
  const float cos_c = dot(s->a, s->b);
  const float k1 = -2.0f * half_sin * sin(0.5f * area - s->alpha);
  const float k2 = sin_phi + sin(s->alpha) * cos_c;
  const float den = k2 * sin_phi + k1 * cos_phi;
  const float one_minus_cos_bp = den != 0.0f ? clamp(2.0f * half_sin * half_sin * (1.0f + cos_c) / den, 0.0f, 2.0f) : 0.0f;
  const float sin_bp = sqrt(fmax(0.0f, one_minus_cos_bp * (2.0f - one_minus_cos_bp)));
  const float3 c_prime = (1.0f - one_minus_cos_bp) * s->a + sin_bp * orthogonal_unit(s->c, s->a);
  /* Then uniformly in 1 - cos of the angle from b along the arc b -> c'. */
  const float cos_theta = 1.0f - u.y * (1.0f - dot(c_prime, s->b));
  const float sin_theta = sqrt(fmax(0.0f, 1.0f - cos_theta * cos_theta));
  return normalize(cos_theta * s->b + sin_theta * orthogonal_unit(c_prime, s->b));
}

/* Where the ray from p along w meets the triangle's plane, as barycentrics
 * (the weights of v1 and v2), clamped onto the triangle. */
inline float2 triangle_barycentrics_along(float3 p, float3 w, float3 v0, float3 v1, float3 v2) {
  const float3 e1 = v1 - v0, e2 = v2 - v0;
  const float3 s1 = cross(w, e2);
  const float divisor = dot(s1, e1);
  if (divisor == 0.0f) return make_float2(1.0f / 3.0f, 1.0f / 3.0f);
  const float3 to_p = p - v0;
  float b1 = dot(to_p, s1) / divisor;
  float b2 = dot(w, cross(to_p, e1)) / divisor;
  b1 = fmax(b1, 0.0f);
  b2 = fmax(b2, 0.0f);
  const float sum = b1 + b2;
  if (sum > 1.0f) {
    b1 /= sum;
    b2 /= sum;
  }
  return make_float2(b1, b2);
}

#endif /* CAUSTICA_LIB_SPHERICAL_SAMPLING_H */
