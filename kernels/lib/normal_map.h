#line 2 "kernels/lib/normal_map.h"
/* Normal maps (glTF's normalTexture; compiled only with HAS_NORMAL_MAPS)
 * and the rule that keeps their shading normals from leaking light.
 *
 * Rules: a texel's rgb c encodes the tangent-space normal 2c - 1 (+x along
 * the tangent, +y along the bitangent, +z along the surface's normal);
 * glTF's `scale` multiplies x and y, and the result is normalised. The
 * frame is the interpolated vertex normal N (the surface point's shading
 * normal before the map), the interpolated tangent T made perpendicular to
 * N, and B = w cross(N, T) with w the tangents' sign (TriangleTangents).
 * Triangles without tangents (zero), and other primitives, keep their
 * normal.
 *
 * Leaks: a mapped normal can lean so far that the mirror direction of the
 * view about it points into the surface; a glossy lobe around that
 * direction would then send most of its samples below the geometric
 * surface, where the integrators end them (lib/bsdf.h's shading_frame and
 * the path vertex drop any direction below the geometric normal: no light
 * passes through), and the surface turns black in patches. Cycles' rule
 * (ensure_valid_specular_reflection, kernel/geom/geom.h) is used for the
 * same reason (normal_with_valid_reflection, lib/optics.h): where the view's reflection R about the mapped normal rises
 * less than q = min(0.9 cos_g, 0.01) above the geometric surface (cos_g the
 * view's cosine with it), the normal becomes the half vector between the
 * view and R lifted to exactly q, keeping R's azimuth (our own solution of
 * Cycles' condition: a closed form, no quadratic). pbrt-v4 applies no such
 * rule and shows the black patches. The rule changes the normal only where
 * it was going to lose most of the light anyway; energy is never created:
 * the furnace test (tests/test_normal_maps.cpp) checks both. */
#ifndef CAUSTICA_LIB_NORMAL_MAP_H
#define CAUSTICA_LIB_NORMAL_MAP_H

#include "lib/optics.h"
#include "lib/surface.h"
#include "lib/texture.h"
#include "shared/types.h"

#if HAS_NORMAL_MAPS
/* Vertex normal n (outward, unit) under normal texture `texture` of scale
 * `scale` at sp's uv, for a path (or photon) arriving along d: the mapped
 * normal, outward; n itself where the triangle has no tangents. */
inline float3 normal_mapped(const SurfacePoint* sp, float3 n, int texture, float scale,
                            __global const TriangleTangents* triangle_tangents, __global const Texture* textures,
                            __global const ushort* texels, Hit hit, float3 d) {
  __global const TriangleTangents* tt = &triangle_tangents[prim_ref_index(hit.prim)];
  const float w0 = 1.0f - hit.u - hit.v;
  float3 t = w0 * tt->t0.xyz + hit.u * tt->t1.xyz + hit.v * tt->t2.xyz;
  t -= dot(t, n) * n;
  const float t2 = dot(t, t);
  if (!(t2 > 1e-12f)) return n; /* no tangents here, or one along the normal */
  t *= rsqrt(t2);
  const float sign = (w0 * tt->t0.w + hit.u * tt->t1.w + hit.v * tt->t2.w) < 0.0f ? -1.0f : 1.0f;
  const float3 b = sign * cross(n, t);
  const float3 c = 2.0f * texture_lookup(textures, (__global const half*)texels, texture, sp->uv) - 1.0f;
  const float3 mapped = (scale * c.x) * t + (scale * c.y) * b + c.z * n;
  const float l2 = dot(mapped, mapped);
  if (!(l2 > 1e-12f) || !isfinite(l2)) return n;
  /* On the viewer's side for the rule, then back to the outward side. */
  const float3 wo = -d;
  const float side = dot(wo, sp->normal) < 0.0f ? -1.0f : 1.0f;
  const float3 ng = side * sp->normal;
  float3 nv = side * (mapped * rsqrt(l2));
  if (dot(nv, ng) < 0.0f) nv -= 2.0f * dot(nv, ng) * ng; /* a texel below the surface: its mirror image */
  return side * normal_with_valid_reflection(nv, ng, wo);
}

/* sp's shading normal under material m's normal map, and its coat's normal
 * (glTF: the clear coat has its own normal map, clearcoatNormalTexture, and
 * without one lies smooth on the vertex normal, whatever the base's map
 * does); sp.uv must be set. */
inline void apply_normal_map(SurfacePoint* sp, __global const Material* m,
                             __global const TriangleTangents* triangle_tangents, __global const Texture* textures,
                             __global const ushort* texels, Hit hit, float3 d) {
  if (prim_ref_type(hit.prim) != PRIM_TRIANGLE) return;
  const float3 vertex_normal = sp->shading_normal;
  if (m->clearcoat_normal_texture >= 0)
    sp->coat_normal = normal_mapped(sp, vertex_normal, m->clearcoat_normal_texture, m->clearcoat_normal_scale,
                                    triangle_tangents, textures, texels, hit, d);
  if (m->normal_texture >= 0)
    sp->shading_normal = normal_mapped(sp, vertex_normal, m->normal_texture, m->normal_scale, triangle_tangents,
                                       textures, texels, hit, d);
}
#endif

#endif /* CAUSTICA_LIB_NORMAL_MAP_H */
