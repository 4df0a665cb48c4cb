#line 2 "kernels/lib/lights/triangle_light.h"
/* Triangle light: an emissive triangle of the scene (made from its shape
 * and material, host/lights/light_table.cpp). p0, p1, p2 = vertices;
 * radiance emitted.xyz on the side of cross(p1 - p0, p2 - p0), or both
 * with LIGHT_TWO_SIDED; emitted.w = area. With LIGHT_EMISSION_TEXTURE (its
 * material has an emission texture, glTF's emissiveTexture) the radiance
 * at a point is emitted.xyz times the texture's texel there, and
 * as_uint(p0.w) is the triangle's index (Triangle, TriangleShading: its
 * texture coordinates), as_uint(p1.w) the texture's; otherwise p0.w, p1.w
 * are 0. p2.w is unused (0). Next-event estimation samples the solid angle
 * the triangle subtends (a spherical triangle) where that is large, by area
 * elsewhere and for a textured light (whose texel is looked up from the
 * sample u, below); photons leave uniformly by area. Functions as in
 * lights/light_common.h; the
 * texel is triangle_light_texel's (lights.h: light_emission_texel), by
 * which callers scale the radiance and photon flux they get: the density
 * stays uniform by area, so the estimators only gain a factor. */
#ifndef CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H

#include "lib/lights/light_common.h"
#include "lib/spherical_sampling.h"
/* The texel's lookup, below (unconditional: an include inside #if would be
 * inlined again where a stage includes these files itself). */
#include "lib/surface.h"
#include "lib/texture.h"

inline float3 triangle_light_normal(__global const Light* l) {
  return normalize(cross(l->p1.xyz - l->p0.xyz, l->p2.xyz - l->p0.xyz));
}

/* The point u places on the triangle, as barycentrics (b1, b2): the weights
 * of p1 and p2. Its position (emission_point) and its texel
 * (triangle_light_texel) both come from here. */
inline float2 triangle_light_barycentrics(float2 u) { return sample_triangle_barycentrics(u); }

/* The point of barycentrics bc and its error bound. */
inline float3 triangle_light_point_at(__global const Light* l, float2 bc, float3* p_error) {
  *p_error = error_gamma(8.0f) * (fabs(l->p0.xyz) + fabs(l->p1.xyz - l->p0.xyz) + fabs(l->p2.xyz - l->p0.xyz));
  return l->p0.xyz + bc.x * (l->p1.xyz - l->p0.xyz) + bc.y * (l->p2.xyz - l->p0.xyz);
}

inline float3 triangle_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  *n = triangle_light_normal(l); /* a plane's normal: the same everywhere */
  return triangle_light_point_at(l, triangle_light_barycentrics(u), p_error);
}

/* Whether p samples the light by solid angle (then *t is its set-up): the
 * one decision both the sampler and the density read; n_l is the light's
 * normal (triangle_light_normal), which both have at hand. */
inline bool triangle_light_by_solid_angle(__global const Light* l, float3 p, float3 n_l, SphericalTriangle* t) {
  /* its texel, or its cut-out, is keyed by the area sample */
  if (l->flags & (LIGHT_EMISSION_TEXTURE | LIGHT_ALPHA)) return false;
  const float3 centroid = (l->p0.xyz + l->p1.xyz + l->p2.xyz) * (1.0f / 3.0f);
  if (!(planar_light_solid_angle_estimate(p, centroid, n_l, l->emitted.w) >= LIGHT_SPHERICAL_MIN_SOLID_ANGLE))
    return false;
  return spherical_triangle_setup(p, l->p0.xyz, l->p1.xyz, l->p2.xyz, t) &&
         t->solid_angle < LIGHT_SPHERICAL_MAX_SOLID_ANGLE;
}

inline bool triangle_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  SphericalTriangle t;
  const float3 n_l = triangle_light_normal(l);
  float3 p_error;
  if (!triangle_light_by_solid_angle(l, p, n_l, &t)) {
    const float3 q = triangle_light_point_at(l, triangle_light_barycentrics(u), &p_error);
    return sample_area_light_point(l, p, q, p_error, n_l, s);
  }
  const float3 w = spherical_triangle_sample(&t, u);
  const float3 q = triangle_light_point_at(l, triangle_barycentrics_along(p, w, l->p0.xyz, l->p1.xyz, l->p2.xyz),
                                           &p_error);
  return sample_planar_light_point(l, p, q, p_error, n_l, 1.0f / t.solid_angle, s);
}

inline float triangle_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  SphericalTriangle t;
  const float3 n_l = triangle_light_normal(l);
  if (triangle_light_by_solid_angle(l, p, n_l, &t)) return 1.0f / t.solid_angle;
  return area_to_solid_angle(p, q, wi, l->emitted.w, n_l);
}

AREA_LIGHT_EMISSION(triangle)

#if HAS_TEXTURES
/* A LIGHT_EMISSION_TEXTURE light's texel at the point u places on it: the
 * texture at the triangle's texture coordinates there (surface.h's
 * triangle_uv, as a hit at that point reads them), filtered as every
 * texture. */
inline float3 triangle_light_texel(__global const Light* l, __global const TriangleShading* triangle_shading,
                                   __global const Texture* textures, __global const half* texels, float2 u) {
  const float2 bc = triangle_light_barycentrics(u);
  const float2 uv = triangle_uv(triangle_shading, as_uint(l->p0.w), bc.x, bc.y);
  return texture_lookup(textures, texels, (int)as_uint(l->p1.w), uv);
}
#endif

#endif /* CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H */
