#line 2 "kernels/lib/lights/spot_light.h"
/* Spot light ("spotlight"): a point light limited to a cone, with glTF
 * KHR_lights_punctual's smooth falloff. p0.xyz = position; p1.xyz = unit
 * axis, p1.w = cos(outer angle); p2.x = cos(inner angle), p2.y = 1 -
 * cos(outer angle) (from the host in double: a narrow cone's cosine rounds
 * to 1); emitted.xyz = intensity I on the axis. Along w at cos c = dot(w, axis) the intensity is
 *     I f(c),  f = clamp((c - cos_o) / (cos_i - cos_o), 0, 1)^2,
 * 1 inside the inner cone and 0 outside the outer one (a hard edge when
 * the two angles are equal). A delta light: only next-event estimation and
 * photons reach it. Functions as in lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_SPOT_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_SPOT_LIGHT_H

#include "lib/lights/light_common.h"

inline float spot_light_falloff(__global const Light* l, float3 w) {
  const float c = dot(w, l->p1.xyz), cos_outer = l->p1.w, cos_inner = l->p2.x;
  if (!(c > cos_outer)) return 0.0f;
  if (c >= cos_inner) return 1.0f;
  const float t = (c - cos_outer) / (cos_inner - cos_outer);
  return t * t;
}

inline bool spot_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  (void)u;
  float d2;
  if (!sample_delta_light_position(l, p, s, &d2)) return false;
  const float falloff = spot_light_falloff(l, -s->wi);
  s->radiance = l->emitted.xyz * falloff / d2;
  return falloff > 0.0f;
}

inline float spot_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  (void)l; (void)p; (void)q; (void)wi;
  return 0.0f;
}

inline float3 spot_light_intensity_toward(__global const Light* l, float3 w) {
  return l->emitted.xyz * spot_light_falloff(l, w);
}

inline float3 spot_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  (void)u;
  *p_error = splat_float3(0.0f);
  *n = splat_float3(0.0f);
  return l->p0.xyz;
}

/* Uniform over the outer cone (density 1 / (2 pi (1 - cos_o))); the flux
 * I f / density. */
inline float3 spot_light_emit(__global const Light* l, float3 point, float3 p_error, float3 n, float2 u, float u_side,
                              float3* origin, float3* dir) {
  (void)u_side; (void)p_error; (void)n;
  const float one_minus_cos_outer = l->p2.y;
  float3 t, b;
  frame_from_normal(l->p1.xyz, &t, &b);
  *dir = frame_to_world(sample_uniform_cone(u, one_minus_cos_outer), t, b, l->p1.xyz);
  *origin = point;
  return l->emitted.xyz * (spot_light_falloff(l, *dir) * 2.0f * M_PI_F * one_minus_cos_outer);
}

inline float3 spot_light_emitted_toward(__global const Light* l, float3 point, float3 p_error, float3 n, float3* dir,
                                        float pdf, float3* origin) {
  (void)n; (void)p_error;
  *origin = point;
  const float falloff = spot_light_falloff(l, *dir);
  if (!(falloff > 0.0f)) *dir = splat_float3(0.0f); /* outside the cone: no flux, no traversal */
  return l->emitted.xyz * (falloff / pdf);
}

#endif /* CAUSTICA_LIB_LIGHTS_SPOT_LIGHT_H */
