#line 2 "kernels/lib/lights/point_light.h"
/* Point light ("pointlight"): p0.xyz = position; emitted.xyz = intensity I
 * (radiance I / d^2 at distance d), the same in every direction. A delta
 * light: only next-event estimation and photons reach it. Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_POINT_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_POINT_LIGHT_H

#include "lib/lights/light_common.h"

inline bool point_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  (void)u;
  float d2;
  if (!sample_delta_light_position(l, p, s, &d2)) return false;
  s->radiance = l->emitted.xyz / d2;
  return true;
}

inline float point_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  (void)l; (void)p; (void)q; (void)wi;
  return 0.0f;
}

inline float3 point_light_intensity_toward(__global const Light* l, float3 w) {
  (void)w;
  return l->emitted.xyz;
}

inline float3 point_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  (void)u;
  *p_error = splat_float3(0.0f);
  *n = splat_float3(0.0f);
  return l->p0.xyz;
}

inline float3 point_light_emit(__global const Light* l, float3 point, float3 p_error, float3 n, float2 u,
                               float u_side, float3* origin, float3* dir) {
  (void)p_error; (void)n; (void)u_side;
  *origin = point;
  *dir = sample_uniform_sphere(u);
  return l->emitted.xyz * (4.0f * M_PI_F);
}

inline float3 point_light_emitted_toward(__global const Light* l, float3 point, float3 p_error, float3 n, float3* dir,
                                         float pdf, float3* origin) {
  (void)n; (void)dir; (void)p_error;
  *origin = point;
  return l->emitted.xyz / pdf;
}

#endif /* CAUSTICA_LIB_LIGHTS_POINT_LIGHT_H */
