#line 2 "kernels/lib/spherical_sampling.h"
/* Directions uniform over the solid angle a planar light subtends: the
 * spherical rectangle (Urena, Fajardo and King 2013, as Cycles samples its
 * area lights) and the spherical triangle (Arvo 1995, as pbrt-v4 samples
 * its triangles). Both return the point on the light that the direction
 * reaches, so the shadow ray aims at a point of the light's own surface as
 * the area samplers' do, and the density is 1 / solid angle.
 *
 * Rules: float32 throughout, and cheap: a light sample is taken at nearly
 * every path vertex, so the set-ups use no inverse trigonometry (the
 * solid angle by Van Oosterom and Strackee's atan2, the angles the warps
 * invert through their sines and cosines) and a sample one sine and
 * cosine (the polynomials of lib/sampling.h, as atan2 is). Callers
 * use these only above LIGHT_SPHERICAL_MIN_SOLID_ANGLE and sample by area
 * below it, where 1/d^2 and the cosine vary little over the light and area
 * sampling loses nothing. The decision is a function of the shading point
 * and the light alone, so the sampler and the MIS density (light_pdf)
 * always agree. Every input of u in [0, 1)^2 gives a finite point on the
 * light (clamped to it);
 * set-ups that cannot hold (the point in the light's plane) say so. */
#ifndef CAUSTICA_LIB_SPHERICAL_SAMPLING_H
#define CAUSTICA_LIB_SPHERICAL_SAMPLING_H

#include "lib/geometry.h"
#include "lib/sampling.h"

/* Below this estimated solid angle (steradians) planar lights are sampled
 * by area: chosen by measurement at equal time (docs/performance.md, "Light
 * sampling by solid angle": 0.01 sr gained 4% of the variance on the
 * Cornell box and cost 22% of its time; 0.1 keeps the whole gain of a
 * large light near a wall, 0.3 loses a part of it). */
#ifndef LIGHT_SPHERICAL_MIN_SOLID_ANGLE
#define LIGHT_SPHERICAL_MIN_SOLID_ANGLE 0.1f
#endif
/* Above this solid angle (a point almost on the light, which then covers
 * nearly a hemisphere) the warps lose their accuracy (pbrt-v4's limit):
 * area sampling again. */
#define LIGHT_SPHERICAL_MAX_SOLID_ANGLE 6.22f

/* The solid angle of a planar light of the given area, unit normal n and
 * centre c seen from p, to first order (area cos / d^2): the cheap test
 * that decides between the two samplers. */
inline float planar_light_solid_angle_estimate(float3 p, float3 c, float3 n, float area) {
  const float3 d = c - p;
  const float d2 = dot(d, d);
  return area * fabs(dot(d, n)) / (d2 * sqrt(d2));
}

/* The solid angle of the triangle with vertices r1, r2, r3 (relative to the
 * point that sees it; not unit), by Van Oosterom and Strackee (1983):
 * tan(omega / 2) = |r1 . (r2 x r3)| / (l1 l2 l3 + (r1 . r2) l3 + (r1 . r3) l2
 * + (r2 . r3) l1). One atan2, and accurate for a small triangle, where a
 * sum of angles less pi cancels. */
inline float triangle_solid_angle(float3 r1, float3 r2, float3 r3, float triple) {
  const float l1 = length(r1), l2 = length(r2), l3 = length(r3);
  const float den = l1 * l2 * l3 + dot(r1, r2) * l3 + dot(r1, r3) * l2 + dot(r2, r3) * l1;
  return 2.0f * atan2_upper(fabs(triple), den);
}

/* A rectangle corner + s edge_x + t edge_y (s, t in [0, 1], the edges
 * orthogonal) seen from o, in the frame of its edges: x, y the unit edge
 * directions, z their normal turned away from the rectangle (so that the
 * rectangle lies at z = z0 < 0), the rectangle spanning [x0, x1] x [y0, y1]. */
typedef struct {
  float3 o, x, y, z;
  float x0, x1, y0, y1, z0;
  float b0, b1;         /* the paper's names */
  float cos_k, sin_k;   /* of its k = 2 pi - g2 - g3 */
  float solid_angle;
} SphericalRectangle;

/* False when o lies in the rectangle's plane (no solid angle) or the set-up
 * does not hold numerically. No inverse trigonometry: the paper's angles
 * enter the sampler through their sines and cosines only, which the
 * corners give algebraically, and the solid angle is two triangles'. */
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
  const float x0 = r->x0, x1 = r->x1, y0 = r->y0, y1 = r->y1, z0 = r->z0, z2 = z0 * z0;
  if (!(z0 < 0.0f)) return false;
  /* The planes through o and consecutive edges have the normals
   * n0 = (0, z0, -y0) / l0, n1 = (-z0, 0, x1) / l1, n2 = (0, -z0, y1) / l2,
   * n3 = (z0, 0, -x0) / l3; the inner angle g_i between n_i and n_i+1 has
   * cos g_i = -n_i . n_i+1 and sin g_i = |n_i x n_i+1| = |z0| |corner| /
   * (l_i l_i+1) at the corner they share. */
  const float l0 = sqrt(z2 + y0 * y0), l2 = sqrt(z2 + y1 * y1), l3 = sqrt(z2 + x0 * x0);
  const float cos_g2 = y1 * x0 / (l2 * l3), sin_g2 = -z0 * sqrt(x0 * x0 + y1 * y1 + z2) / (l2 * l3);
  const float cos_g3 = -x0 * y0 / (l3 * l0), sin_g3 = -z0 * sqrt(x0 * x0 + y0 * y0 + z2) / (l3 * l0);
  r->cos_k = cos_g2 * cos_g3 - sin_g2 * sin_g3;
  r->sin_k = -(sin_g2 * cos_g3 + cos_g2 * sin_g3);
  r->b0 = -y0 / l0; /* n0.z */
  r->b1 = y1 / l2;  /* n2.z */
  /* Two triangles (v00, v10, v11) and (v00, v11, v01); the triple product
   * of each is z0 (x1 - x0) (y1 - y0). */
  const float triple = z0 * len_x * len_y;
  const float3 v00 = make_float3(x0, y0, z0), v10 = make_float3(x1, y0, z0);
  const float3 v11 = make_float3(x1, y1, z0), v01 = make_float3(x0, y1, z0);
  r->solid_angle = triangle_solid_angle(v00, v10, v11, triple) + triangle_solid_angle(v00, v11, v01, triple);
  return r->solid_angle > 0.0f && isfinite(r->solid_angle);
}

/* The point of the rectangle in direction of the sample u (density
 * 1 / solid_angle over directions); *p_error bounds its error. */
inline float3 spherical_rectangle_sample(const SphericalRectangle* r, float2 u, float3* p_error) {
  /* The x at which the solid angle left of x is u.x of the whole: the
   * paper's au = u.x S + k, its sine and cosine by the angle sum. */
  float cos_us;
  const float sin_us = sin_cos_full_turn(u.x * r->solid_angle, &cos_us);
  const float cos_au = cos_us * r->cos_k - sin_us * r->sin_k;
  const float sin_au = sin_us * r->cos_k + cos_us * r->sin_k;
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

/* A spherical triangle: the unit directions from p to the vertices, the
 * cosine and sine of its inner angle alpha at a, its solid angle; false
 * when p lies in the triangle's plane (or on an edge's line) or the set-up
 * does not hold numerically. */
typedef struct {
  float3 a, b, c;
  float cos_alpha, sin_alpha, solid_angle;
} SphericalTriangle;

inline bool spherical_triangle_setup(float3 p, float3 v0, float3 v1, float3 v2, SphericalTriangle* s) {
  s->a = normalize(v0 - p);
  s->b = normalize(v1 - p);
  s->c = normalize(v2 - p);
  const float3 n_ab = cross(s->a, s->b), n_bc = cross(s->b, s->c), n_ca = cross(s->c, s->a);
  const float l_ab = length(n_ab), l_ca = length(n_ca);
  if (!(l_ab > 0.0f && length(n_bc) > 0.0f && l_ca > 0.0f)) return false;
  /* alpha: between the planes (a, b) and (a, c), normals n_ab and -n_ca. */
  const float inv = 1.0f / (l_ab * l_ca);
  s->cos_alpha = -dot(n_ab, n_ca) * inv;
  s->sin_alpha = length(cross(n_ab, n_ca)) * inv;
  s->solid_angle =
      2.0f * atan2_upper(fabs(dot(s->a, n_bc)), 1.0f + dot(s->a, s->b) + dot(s->b, s->c) + dot(s->c, s->a));
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
   * and t its sine and cosine, by the angle sum from sin and cos of
   * area / 2: one sincos in all):
   *   1 - cos b' = 2 sin^2(area / 2) (1 + cos c) / (k2 sin phi + k1 cos phi),
   *   k1 = cos phi - cos alpha = -2 sin(area / 2) sin(area / 2 - alpha),
   *   k2 = sin phi + sin alpha cos c. */
  float half_cos;
  const float half_sin = sin_cos_half_turn(fmin(0.5f * area, M_PI_F), &half_cos);
  const float sin_area = 2.0f * half_sin * half_cos, cos_area = 1.0f - 2.0f * half_sin * half_sin;
  const float sin_phi = sin_area * s->cos_alpha - cos_area * s->sin_alpha;
  const float cos_phi = cos_area * s->cos_alpha + sin_area * s->sin_alpha;
  const float cos_c = dot(s->a, s->b);
  const float k1 = -2.0f * half_sin * (half_sin * s->cos_alpha - half_cos * s->sin_alpha);
  const float k2 = sin_phi + s->sin_alpha * cos_c;
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
