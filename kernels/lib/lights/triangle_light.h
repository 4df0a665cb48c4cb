#line 2 "kernels/lib/lights/triangle_light.h"
/* Triangle light: an emissive triangle of the scene (made from its shape
 * and material, host/lights/shape_lights.cpp). p0, p1, p2 = vertices;
 * radiance emitted.xyz on the side of cross(p1 - p0, p2 - p0), or both
 * with LIGHT_TWO_SIDED; emitted.w = area. Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H

#include "lib/lights/light_common.h"

inline float3 triangle_light_normal(__global const Light* l) {
  return normalize(cross(l->p1.xyz - l->p0.xyz, l->p2.xyz - l->p0.xyz));
}

inline float3 triangle_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  const float2 bc = sample_triangle_barycentrics(u);
  const float3 q = l->p0.xyz + bc.x * (l->p1.xyz - l->p0.xyz) + bc.y * (l->p2.xyz - l->p0.xyz);
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz - l->p0.xyz) + fabs(l->p2.xyz - l->p0.xyz));
  *n = triangle_light_normal(l); /* a plane's normal: the same everywhere */
  return q;
}

inline float triangle_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  return area_to_solid_angle(p, q, wi, l->emitted.w, triangle_light_normal(l));
}

AREA_LIGHT_SAMPLE_BY_AREA(triangle)
AREA_LIGHT_EMISSION(triangle)

#endif /* CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H */
