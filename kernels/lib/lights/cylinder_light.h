#line 2 "kernels/lib/lights/cylinder_light.h"
/* Cylinder light: an emissive cylinder of the scene (made from its shape
 * and material, host/lights/shape_lights.cpp). p0.xyz = centre, p0.w =
 * radius; p1.xyz = unit axis, p1.w = half length; radiance emitted.xyz
 * outward from the side and both caps; emitted.w = area. Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_CYLINDER_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_CYLINDER_LIGHT_H

#include "lib/lights/light_common.h"

/* The outward normal at point q of the side or a cap. */
inline float3 cylinder_light_normal(__global const Light* l, float3 q) {
  const float3 rel = q - l->p0.xyz, axis = l->p1.xyz;
  const float z = dot(rel, axis), h = l->p1.w;
  if (fabs(z) >= h * (1.0f - 1e-4f)) return z > 0.0f ? axis : -axis;
  return normalize(rel - z * axis);
}

/* A point on the side or caps, uniform by area, and the outward normal of
 * the part it was drawn on. The part is known here; recovered from the
 * point (cylinder_light_normal) it is not, once the point's rounding
 * exceeds the cap tolerance: 1e5 from the origin a cap point of a unit
 * cylinder read as a side point, whose radial normal faced shading points
 * the cap faced away from, and 1 in 15 shadow rays then had to cross the
 * light (tests/stiff/test_shadow_rays.cpp). */
inline float3 cylinder_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* normal) {
  const float r = l->p0.w, h = l->p1.w;
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + splat_float3(r + h));
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
  const float2 d = r * sample_concentric_disk(make_float2(fmod(pick, cap) / cap, u.y));
  *normal = sgn * axis;
  return l->p0.xyz + sgn * h * axis + d.x * t + d.y * b;
}

inline float cylinder_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  return area_to_solid_angle(p, q, wi, l->emitted.w, cylinder_light_normal(l, q));
}

AREA_LIGHT_SAMPLE_BY_AREA(cylinder)
AREA_LIGHT_EMISSION(cylinder)

#endif /* CAUSTICA_LIB_LIGHTS_CYLINDER_LIGHT_H */
