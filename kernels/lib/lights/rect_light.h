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

inline float rect_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  return area_to_solid_angle(p, q, wi, l->emitted.w, rect_light_normal(l));
}

AREA_LIGHT_SAMPLE_BY_AREA(rect)
AREA_LIGHT_EMISSION(rect)

#endif /* CAUSTICA_LIB_LIGHTS_RECT_LIGHT_H */
