#line 2 "kernels/lib/lights/sphere_light.h"
/* Sphere light ("spherelight", and every emissive sphere of the scene):
 * p0.xyz = centre, p0.w = radius; radiance emitted.xyz outward;
 * emitted.w = area. Next-event estimation samples the cone the sphere
 * subtends; photons leave uniformly by area. Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_SPHERE_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_SPHERE_LIGHT_H

#include "lib/lights/light_common.h"

/* Uniform in the cone of directions the sphere subtends, but the point is
 * placed on the sphere from the cone's angles (pbrt-v4's Sphere::Sample)
 * rather than found as the nearest root along the sampled direction: near
 * the silhouette that root is a difference of nearly equal numbers of the
 * size of the distance to the centre, and it put the point up to 1e-3 of
 * the radius behind the front surface, so that ~1 in 100 shadow rays were
 * stopped by the light itself (tests/stiff/test_shadow_rays.cpp). Here the
 * point is the centre plus the radius times a unit vector: exact to a few
 * roundings of the sphere's size and position, wherever the shading point
 * is. */
inline bool sphere_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
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
  s->p_error = error_gamma(6.0f) * (fabs(c) + splat_float3(r));
  const float3 d = s->point - p;
  s->distance = length(d);
  if (!(s->distance > 0.0f)) return false;
  s->wi = d / s->distance;
  s->radiance = l->emitted.xyz;
  s->pdf = pdf_uniform_cone(one_minus_cos_max);
  return true;
}

inline float sphere_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  (void)q; (void)wi;
  const float3 to_c = l->p0.xyz - p;
  const float d2 = dot(to_c, to_c);
  const float r = l->p0.w;
  if (!(d2 > r * r)) return 0.0f;
  return pdf_uniform_cone(sphere_cone_one_minus_cos(d2, r * r));
}

/* Uniform by area: the centre plus the radius times a unit vector, a few
 * roundings each (8 bounds them all). */
inline float3 sphere_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  *n = sample_uniform_sphere(u);
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + splat_float3(l->p0.w));
  return l->p0.xyz + l->p0.w * *n;
}

AREA_LIGHT_EMISSION(sphere)

#endif /* CAUSTICA_LIB_LIGHTS_SPHERE_LIGHT_H */
