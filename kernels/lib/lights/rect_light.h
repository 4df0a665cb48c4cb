#line 2 "kernels/lib/lights/rect_light.h"
/* Rectangle light ("arealight"): p0.xyz = centre, p1.xyz / p2.xyz = full
 * edge vectors u, v; emits radiance emitted.xyz on the side of cross(u, v)
 * only; emitted.w = area. Its two triangles are scene geometry in path
 * mode (host/lights/rect_light.cpp). Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H

#include "lib/lights/light_common.h"

inline float3 rect_light_normal(__global const Light* l) { return normalize(cross(l->p1.xyz, l->p2.xyz)); }

/* Uniform by area; the bound covers the sum of the centre and two edge
 * terms, a few roundings each (8 bounds them all). */
inline float3 rect_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  const float3 q = sample_rectangle(l->p0.xyz, l->p1.xyz, l->p2.xyz, u);
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz) + fabs(l->p2.xyz));
  *n = rect_light_normal(l);
  return q;
}

inline bool rect_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  float3 p_error, n_l;
  const float3 q = rect_light_emission_point(l, u, &p_error, &n_l);
  return sample_area_light_point(l, p, q, p_error, n_l, s);
}

inline float rect_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  return area_to_solid_angle(p, q, wi, l->emitted.w, rect_light_normal(l));
}

inline float3 rect_light_intensity_toward(__global const Light* l, float3 w) {
  (void)w;
  return l->emitted.xyz;
}

inline float3 rect_light_emit(__global const Light* l, float3 point, float3 p_error, float3 n, float2 u, float u_side,
                              float3* origin, float3* dir) {
  return emit_area_light(l, point, p_error, n, u, u_side, origin, dir);
}

inline float3 rect_light_emitted_toward(__global const Light* l, float3 point, float3 p_error, float3 n, float3* dir,
                                        float pdf, float3* origin) {
  return area_light_emitted_toward(l, point, p_error, n, dir, pdf, origin);
}

#endif /* CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H */
