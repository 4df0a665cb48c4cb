#line 2 "kernels/lib/lights/triangle_light.h"
/* Triangle light: an emissive triangle of the scene (made from its shape
 * and material, host/lights/light_table.cpp). p0, p1, p2 = vertices;
 * radiance emitted.xyz on the side of cross(p1 - p0, p2 - p0), or both
 * with LIGHT_TWO_SIDED; emitted.w = area. With LIGHT_EMISSION_TEXTURE (its
 * material has an emission texture, glTF's emissiveTexture) the radiance
 * at a point is emitted.xyz times the texture's texel there, and
 * as_uint(p0.w) is the triangle's index (Triangle, TriangleShading: its
 * texture coordinates), as_uint(p1.w) the texture's; otherwise p0.w, p1.w
 * are 0. p2.w is unused (0). Functions as in lights/light_common.h; the
 * texel is triangle_light_texel's (lights.h: light_emission_texel), by
 * which callers scale the radiance and photon flux they get: the density
 * stays uniform by area, so the estimators only gain a factor. */
#ifndef CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_TRIANGLE_LIGHT_H

#include "lib/lights/light_common.h"
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

inline float3 triangle_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  const float2 bc = triangle_light_barycentrics(u);
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
