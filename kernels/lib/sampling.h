#line 2 "kernels/lib/sampling.h"
/* Warps of uniform samples onto the shapes the path tracer samples, each
 * with its density.
 *
 * Rules: u is in [0, 1)^2; directions are unit vectors in a local frame
 * whose z axis is the surface normal (frame_from_normal); densities are per
 * unit solid angle for directions and per unit area for points. Every warp
 * is finite for every u in [0, 1)^2 (u = 0 included) and keeps the
 * stratification of its input (no rejection). */
#ifndef CAUSTICA_LIB_SAMPLING_H
#define CAUSTICA_LIB_SAMPLING_H

#include "shared/compat.h"

/* Shirley-Chiu concentric map: the unit square onto the unit disk, area
 * preserving up to a constant and with low distortion. */
/* sin and cos of |a| <= pi/4 by the minimax polynomials of Cephes' sinf and
 * cosf (within about 1 ulp there): no argument reduction, which in PoCL's
 * sincos was a tenth of the path tracer's shade stage. */
inline float sin_cos_quarter_turn(float a, float* cos_a) {
  const float z = a * a;
  *cos_a = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.0f;
  return ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * a + a;
}

/* sin and cos of 0 <= a <= pi, by the quarter-turn polynomials after
 * folding onto [0, pi/4] (PoCL's sincos spends more on its general
 * argument reduction than on the polynomials). */
inline float sin_cos_half_turn(float a, float* cos_a) {
  const bool upper = a > M_PI_2_F; /* sin(a) = sin(pi - a), cos(a) = -cos(pi - a) */
  const float h = upper ? M_PI_F - a : a;
  float s, c;
  if (h > M_PI_4_F) { /* sin(h) = cos(pi/2 - h) */
    c = sin_cos_quarter_turn(M_PI_2_F - h, &s);
  } else {
    s = sin_cos_quarter_turn(h, &c);
  }
  *cos_a = upper ? -c : c;
  return s;
}

/* The same for 0 <= a <= 2 pi. */
inline float sin_cos_full_turn(float a, float* cos_a) {
  if (!(a > M_PI_F)) return sin_cos_half_turn(fmax(a, 0.0f), cos_a);
  float c;
  const float s = sin_cos_half_turn(fmin(a - M_PI_F, M_PI_F), &c); /* sin(a) = -sin(a - pi) */
  *cos_a = -c;
  return -s;
}

/* atan2(y, x) for y >= 0 (a result in [0, pi]), by Cephes' atanf
 * polynomial (within about 2 ulp) after its reduction onto
 * |t| <= tan(pi/8): PoCL's atan2 cost as much as the rest of a light
 * sample. */
inline float atan2_upper(float y, float x) {
  const float ax = fabs(x);
  if (!(ax > 0.0f || y > 0.0f)) return 0.0f;
  float t, base;
  if (y > 2.414213562373095f * ax) { /* beyond tan(3 pi/8): pi/2 - atan(ax / y) */
    t = -ax / y;
    base = M_PI_2_F;
  } else if (y > 0.4142135623730950f * ax) { /* beyond tan(pi/8): pi/4 + atan((y - ax) / (y + ax)) */
    t = (y - ax) / (y + ax);
    base = M_PI_4_F;
  } else {
    t = y / ax;
    base = 0.0f;
  }
  const float z = t * t;
  const float r =
      base + (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * t + t;
  return x < 0.0f ? M_PI_F - r : r;
}

inline float2 sample_concentric_disk(float2 u) {
  const float2 o = 2.0f * u - 1.0f;
  if (o.x == 0.0f && o.y == 0.0f) return make_float2(0.0f, 0.0f);
  float c;
  if (fabs(o.x) > fabs(o.y)) { /* theta = pi/4 oy/ox */
    const float s = sin_cos_quarter_turn(M_PI_4_F * (o.y / o.x), &c);
    return o.x * make_float2(c, s);
  }
  /* theta = pi/2 - a, a = pi/4 ox/oy: cos theta = sin a, sin theta = cos a */
  const float s = sin_cos_quarter_turn(M_PI_4_F * (o.x / o.y), &c);
  return o.y * make_float2(s, c);
}

/* Malley: a disk point lifted onto the hemisphere; density cos(theta) / pi. */
inline float3 sample_cosine_hemisphere(float2 u) {
  const float2 d = sample_concentric_disk(u);
  return make_float3(d.x, d.y, sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y)));
}

inline float pdf_cosine_hemisphere(float cos_theta) { return fmax(cos_theta, 0.0f) * M_1_PI_F; }

/* Uniform over the directions within angle acos(cos_max) of +z; density
 * 1 / (2 pi (1 - cos_max)). 1 - cos_max is passed as well, because for a
 * small cone cos_max rounds to 1 and the difference would vanish. */
inline float3 sample_uniform_cone(float2 u, float one_minus_cos_max) {
  const float one_minus_cos = u.x * one_minus_cos_max;
  const float cos_theta = 1.0f - one_minus_cos;
  const float sin_theta = sqrt(fmax(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  float cos_phi;
  const float sin_phi = sincos(2.0f * M_PI_F * u.y, &cos_phi);
  return make_float3(cos_phi * sin_theta, sin_phi * sin_theta, cos_theta);
}

inline float pdf_uniform_cone(float one_minus_cos_max) { return 1.0f / (2.0f * M_PI_F * one_minus_cos_max); }

/* 1 - cos of the half-angle a sphere of squared radius r2 subtends from a
 * point at squared distance d2 > r2, without the cancellation of
 * 1 - sqrt(1 - r2 / d2) for a small or far sphere. Sampling the cone
 * (sample_uniform_cone) samples every direction that can reach the sphere. */
inline float sphere_cone_one_minus_cos(float d2, float r2) {
  const float sin2 = fmin(r2 / d2, 1.0f);
  return sin2 / (1.0f + sqrt(1.0f - sin2));
}

/* Uniform over the sphere; density 1 / (4 pi). */
inline float3 sample_uniform_sphere(float2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = sqrt(fmax(0.0f, 1.0f - z * z));
  float cos_phi;
  const float sin_phi = sincos(2.0f * M_PI_F * u.y, &cos_phi);
  return make_float3(r * cos_phi, r * sin_phi, z);
}

/* Uniform over the rectangle centre + s edge_u + t edge_v, s, t in
 * [-1/2, 1/2] (the area lights of scene.h); density 1 / |edge_u x edge_v|. */
inline float3 sample_rectangle(float3 centre, float3 edge_u, float3 edge_v, float2 u) {
  return centre + (u.x - 0.5f) * edge_u + (u.y - 0.5f) * edge_v;
}

/* Barycentrics (b1, b2) uniform over a triangle, by Heitz's low-distortion
 * map (2019) rather than the square-root one, which crowds one corner. */
inline float2 sample_triangle_barycentrics(float2 u) {
  float b1, b2;
  if (u.y > u.x) {
    b1 = 0.5f * u.x;
    b2 = u.y - b1;
  } else {
    b2 = 0.5f * u.y;
    b1 = u.x - b2;
  }
  return make_float2(b1, b2);
}

/* An orthonormal frame (t, b, n) around the unit vector n, without a branch
 * on the axis (Duff et al. 2017). */
inline void frame_from_normal(float3 n, float3* t, float3* b) {
  const float sign = copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  *t = make_float3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  *b = make_float3(c, sign + n.y * n.y * a, -n.y);
}

inline float3 frame_to_world(float3 v, float3 t, float3 b, float3 n) { return v.x * t + v.y * b + v.z * n; }

inline float3 frame_to_local(float3 world, float3 t, float3 b, float3 n) {
  return make_float3(dot(world, t), dot(world, b), dot(world, n));
}

#endif /* CAUSTICA_LIB_SAMPLING_H */
