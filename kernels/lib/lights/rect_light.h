#line 2 "kernels/lib/lights/rect_light.h"
/* Rectangle light ("arealight"): p0.xyz = centre, p1.xyz / p2.xyz = full
 * edge vectors u, v; emits radiance emitted.xyz on the side of cross(u, v)
 * only; emitted.w = area. Its two triangles are scene geometry in path
 * mode (host/lights/rect_light.cpp). Next-event estimation samples the
 * solid angle it subtends (a spherical rectangle) where that is large,
 * by area elsewhere and for a parallelogram (edges not orthogonal);
 * photons leave uniformly by area. Functions as in lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H

#include "lib/lights/light_common.h"
#include "lib/spherical_sampling.h"

inline float3 rect_light_normal(__global const Light* l) { return normalize(cross(l->p1.xyz, l->p2.xyz)); }

/* Uniform by area; the bound covers the sum of the centre and two edge
 * terms, a few roundings each (8 bounds them all). */
inline float3 rect_light_point_at(__global const Light* l, float2 u, float3* p_error) {
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz) + fabs(l->p2.xyz));
  return sample_rectangle(l->p0.xyz, l->p1.xyz, l->p2.xyz, u);
}

inline float3 rect_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  *n = rect_light_normal(l);
  return rect_light_point_at(l, u, p_error);
}

/* Whether p samples the light by solid angle (then *r is its set-up): the
 * one decision both the sampler and the density read; n_l is the light's
 * normal (rect_light_normal), which both have at hand. */
inline bool rect_light_by_solid_angle(__global const Light* l, float3 p, float3 n_l, SphericalRectangle* r) {
  const float3 eu = l->p1.xyz, ev = l->p2.xyz;
  if (fabs(dot(eu, ev)) > 1e-4f * length(eu) * length(ev)) return false; /* a parallelogram */
  if (!(planar_light_solid_angle_estimate(p, l->p0.xyz, n_l, l->emitted.w) >= LIGHT_SPHERICAL_MIN_SOLID_ANGLE))
    return false;
  return spherical_rectangle_setup(p, l->p0.xyz - 0.5f * (eu + ev), eu, ev, r) &&
         r->solid_angle < LIGHT_SPHERICAL_MAX_SOLID_ANGLE;
}

inline bool rect_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  SphericalRectangle r;
  const float3 n_l = rect_light_normal(l);
  float3 p_error;
  if (!rect_light_by_solid_angle(l, p, n_l, &r))
    return sample_area_light_point(l, p, rect_light_point_at(l, u, &p_error), p_error, n_l, s);
  const float3 q = spherical_rectangle_sample(&r, u, &p_error);
  return sample_planar_light_point(l, p, q, p_error, n_l, 1.0f / r.solid_angle, s);
}

inline float rect_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  SphericalRectangle r;
  const float3 n_l = rect_light_normal(l);
  if (rect_light_by_solid_angle(l, p, n_l, &r)) return 1.0f / r.solid_angle;
  return area_to_solid_angle(p, q, wi, l->emitted.w, n_l);
}

AREA_LIGHT_EMISSION(rect)

#endif /* CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H */
