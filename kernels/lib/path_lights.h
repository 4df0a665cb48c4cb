#line 2 "kernels/lib/path_lights.h"
/* Sampling the path tracer's lights (PathLight, shared/types.h) from a
 * shading point, and the density with which that sampling would have
 * picked a direction that a BSDF-sampled ray found (for MIS).
 *
 * Rules: densities are per unit solid angle at the shading point and
 * include the probability of picking the light; a point light is a delta
 * (its density is the pick probability alone, and MIS never weights it).
 * Radiance conventions (scenes/FORMAT.md): a point light's intensity I gives
 * radiance I / d^2; area lights emit their radiance `emitted` from their
 * front side (rectangles: cross(u, v); triangles: counter-clockwise;
 * spheres and cylinders: outward), both sides with LIGHT_TWO_SIDED. Which
 * side a hit sees is decided by the shade stage from the surface normal. */
#ifndef CAUSTICA_LIB_PATH_LIGHTS_H
#define CAUSTICA_LIB_PATH_LIGHTS_H

#include "lib/sampling.h"
#include "shared/types.h"

/* Programs whose scene has point lights only leave area-light sampling out
 * (-DHAS_AREA_LIGHTS=0). */
#ifndef HAS_AREA_LIGHTS
#define HAS_AREA_LIGHTS 1
#endif

typedef struct {
  float3 wi;       /* unit direction toward the light */
  float distance;  /* to the sampled point */
  float3 point;    /* the sampled point: the shadow ray aims at it (spawn_ray_to, geometry.h) */
  float3 p_error;  /* bound on the sampled point's error per component (shadow_ray_tmax, geometry.h) */
  float3 normal;   /* the light's surface normal at the point, either side; zero for a point light */
  float3 radiance; /* arriving along -wi, before visibility */
  float pdf;       /* solid angle x pick probability; the pick probability alone for a point */
  bool delta;
} LightSample;

/* The light whose prefix probability first exceeds u (binary search). */
inline uint pick_light(__global const PathLight* lights, uint count, float u) {
  uint lo = 0u, hi = count - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) / 2u;
    if (u < lights[mid].select_cdf) hi = mid;
    else lo = mid + 1u;
  }
  return lo;
}

/* The emitting side's normal at point q of a rectangle, triangle or
 * cylinder light. */
inline float3 light_normal(__global const PathLight* l, float3 q) {
  if (l->kind == LIGHT_RECT) return normalize(cross(l->p1.xyz, l->p2.xyz));
  if (l->kind == LIGHT_CYLINDER) {
    const float3 rel = q - l->p0.xyz, axis = l->p1.xyz;
    const float z = dot(rel, axis), h = l->p1.w;
    if (fabs(z) >= h * (1.0f - 1e-4f)) return z > 0.0f ? axis : -axis;
    return normalize(rel - z * axis);
  }
  return normalize(cross(l->p1.xyz - l->p0.xyz, l->p2.xyz - l->p0.xyz));
}

/* Solid-angle density (without the pick probability) of reaching point q
 * with normal n_l on an area light of the given area from p. */
inline float area_to_solid_angle(float3 p, float3 q, float3 wi, float area, float3 n_l) {
  const float cos_l = fabs(dot(wi, n_l));
  if (!(cos_l > 0.0f) || !(area > 0.0f)) return 0.0f;
  const float3 d = q - p;
  return dot(d, d) / (cos_l * area);
}

/* Does the light's surface at q, with emitting-side normal n_l, shine
 * toward the point that wi (from that point toward q) comes from? */
inline bool light_faces(__global const PathLight* l, float3 wi, float3 n_l) {
  return (l->flags & LIGHT_TWO_SIDED) != 0u || dot(wi, n_l) < 0.0f;
}

/* A point on the cylinder's side or caps, uniform by area, and the outward
 * normal of the part it was drawn on. The part is known here; recovered
 * from the point (light_normal) it is not, once the point's rounding
 * exceeds light_normal's cap tolerance: 1e5 from the origin a cap point of
 * a unit cylinder read as a side point, whose radial normal faced shading
 * points the cap faced away from, and 1 in 15 shadow rays then had to
 * cross the light (tests/stiff/test_shadow_rays.cpp). */
inline float3 sample_cylinder_surface(__global const PathLight* l, float2 u, float3* normal) {
  const float r = l->p0.w, h = l->p1.w;
  const float side = 4.0f * M_PI_F * r * h, cap = M_PI_F * r * r;
  const float3 axis = l->p1.xyz;
  float3 t, b;
  frame_from_normal(axis, &t, &b);
  float pick = u.x * (side + 2.0f * cap);
  if (pick < side) {
    float cos_phi;
    const float sin_phi = sincos(2.0f * M_PI_F * (pick / side), &cos_phi);
    *normal = cos_phi * t + sin_phi * b;
    return l->p0.xyz + (2.0f * u.y - 1.0f) * h * axis + r * *normal;
  }
  pick -= side;
  const float sgn = pick < cap ? 1.0f : -1.0f;
  const float2 d = r * sample_concentric_disk((float2)(fmod(pick, cap) / cap, u.y));
  *normal = sgn * axis;
  return l->p0.xyz + sgn * h * axis + d.x * t + d.y * b;
}

/* A point uniform by area on an area light's surface (any kind but a
 * point), its error bound per component and the surface normal there (the
 * emitting side of one-sided lights). The photon pass emits from here; the
 * path tracer samples spheres by solid angle instead (sample_light). */
inline float3 sample_light_surface(__global const PathLight* l, float2 u, float3* p_error, float3* normal) {
  /* Sums of the base point and at most two terms of the light's size, a
   * few roundings each (8 bounds them all). */
  if (l->kind == LIGHT_SPHERE) {
    *normal = sample_uniform_sphere(u);
    *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + (float3)(l->p0.w));
    return l->p0.xyz + l->p0.w * *normal;
  }
  if (l->kind == LIGHT_CYLINDER) {
    *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + (float3)(l->p0.w + l->p1.w));
    return sample_cylinder_surface(l, u, normal);
  }
  float3 q;
  if (l->kind == LIGHT_RECT) {
    q = sample_rectangle(l->p0.xyz, l->p1.xyz, l->p2.xyz, u);
    *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz) + fabs(l->p2.xyz));
  } else {
    const float2 bc = sample_triangle_barycentrics(u);
    q = l->p0.xyz + bc.x * (l->p1.xyz - l->p0.xyz) + bc.y * (l->p2.xyz - l->p0.xyz);
    *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz - l->p0.xyz) + fabs(l->p2.xyz - l->p0.xyz));
  }
  *normal = light_normal(l, q); /* a plane's normal: the same everywhere */
  return q;
}

inline bool sample_light(__global const PathLight* l, float pick_probability, float3 p, float2 u, LightSample* s) {
  s->delta = false;
  if (l->kind == LIGHT_POINT) {
    const float3 d = l->p0.xyz - p;
    const float d2 = dot(d, d);
    if (!(d2 > 0.0f)) return false;
    s->distance = sqrt(d2);
    s->wi = d / s->distance;
    s->point = l->p0.xyz;
    s->p_error = (float3)(0.0f); /* the point is exact */
    s->normal = (float3)(0.0f);
    s->radiance = l->emitted.xyz / d2;
    s->pdf = pick_probability;
    s->delta = true;
    return true;
  }
#if HAS_AREA_LIGHTS
  if (l->kind == LIGHT_SPHERE) {
    /* Uniform in the cone of directions the sphere subtends, but the point
     * is placed on the sphere from the cone's angles (pbrt-v4's
     * Sphere::Sample) rather than found as the nearest root along the
     * sampled direction: near the silhouette that root is a difference of
     * nearly equal numbers of the size of the distance to the centre, and
     * it put the point up to 1e-3 of the radius behind the front surface,
     * so that ~1 in 100 shadow rays were stopped by the light itself
     * (tests/stiff/test_shadow_rays.cpp). Here the point is the centre plus
     * the radius times a unit vector: exact to a few roundings of the
     * sphere's size and position, wherever the shading point is. */
    const float3 c = l->p0.xyz;
    const float r = l->p0.w;
    const float3 to_c = c - p;
    const float d2 = dot(to_c, to_c);
    if (!(d2 > r * r)) return false; /* inside the light: it is hit, not sampled */
    const float sin2_max = r * r / d2;
    const float one_minus_cos_max = sphere_cone_one_minus_cos(d2, r * r);
    const float one_minus_cos = u.x * one_minus_cos_max;
    const float cos_theta = 1.0f - one_minus_cos;
    const float sin2_theta = one_minus_cos * (2.0f - one_minus_cos);
    /* The angle alpha at the centre between the direction back to p and the
     * sampled point (law of sines in the triangle p, centre, point). */
    const float cos_alpha = sin2_theta / sqrt(sin2_max) + cos_theta * sqrt(fmax(0.0f, 1.0f - sin2_theta / sin2_max));
    const float sin_alpha = sqrt(fmax(0.0f, 1.0f - cos_alpha * cos_alpha));
    float cos_phi;
    const float sin_phi = sincos(2.0f * M_PI_F * u.y, &cos_phi);
    const float3 axis = to_c * rsqrt(d2);
    float3 t, b;
    frame_from_normal(axis, &t, &b);
    const float3 n = sin_alpha * (cos_phi * t + sin_phi * b) - cos_alpha * axis;
    s->point = c + r * n;
    s->normal = n;
    /* c + r n: n is unit to a few roundings, each of size r, and the sum
     * rounds once at |point|. */
    s->p_error = error_gamma(6.0f) * (fabs(c) + (float3)(r));
    const float3 d = s->point - p;
    s->distance = length(d);
    if (!(s->distance > 0.0f)) return false;
    s->wi = d / s->distance;
    s->radiance = l->emitted.xyz;
    s->pdf = pick_probability * pdf_uniform_cone(one_minus_cos_max);
    return s->pdf > 0.0f;
  }
  float3 n_l;
  const float3 q = sample_light_surface(l, u, &s->p_error, &n_l);
  const float3 d = q - p;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return false;
  s->distance = sqrt(d2);
  s->wi = d / s->distance;
  s->point = q;
  if (!light_faces(l, s->wi, n_l)) return false;
  s->normal = n_l;
  s->radiance = l->emitted.xyz;
  s->pdf = pick_probability * area_to_solid_angle(p, q, s->wi, l->emitted.w, n_l);
  return s->pdf > 0.0f;
#else
  return false;
#endif
}

/* What sample_light's density would have been for the direction wi from p
 * that reached point q of light l (a BSDF-sampled ray's hit). */
inline float light_pdf(__global const PathLight* l, float pick_probability, float3 p, float3 q, float3 wi) {
#if !HAS_AREA_LIGHTS
  return 0.0f;
#endif
  if (l->kind == LIGHT_POINT) return 0.0f;
  if (l->kind == LIGHT_SPHERE) {
    const float3 to_c = l->p0.xyz - p;
    const float d2 = dot(to_c, to_c);
    const float r = l->p0.w;
    if (!(d2 > r * r)) return 0.0f;
    return pick_probability * pdf_uniform_cone(sphere_cone_one_minus_cos(d2, r * r));
  }
  return pick_probability * area_to_solid_angle(p, q, wi, l->emitted.w, light_normal(l, q));
}

#endif /* CAUSTICA_LIB_PATH_LIGHTS_H */
