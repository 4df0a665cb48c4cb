#line 2 "kernels/lib/geometry.h"
/* Ray/hit vocabulary shared by the intersection, traversal and shading code.
 *
 * Rules: OpenCL C 1.2, float32 only; programs may be built with
 * -cl-fast-relaxed-math, so nothing here may produce or test for inf/NaN
 * (finite sentinels such as RAY_T_FAR instead). */
#ifndef CAUSTICA_LIB_GEOMETRY_H
#define CAUSTICA_LIB_GEOMETRY_H

#include "shared/types.h"

/* Hit, RAY_T_FAR and CYL_PART_* live in shared/types.h (the host trace
 * shares them). */

/* The traversal's view of the scene: the wide BVH (nodes, triangle blocks,
 * refs of the sphere/cylinder leaves), the primitive arrays, and the
 * triangles' alpha cut-outs with the texels they read (read only with
 * HAS_ALPHA_CUTOUTS, lib/alpha_cutout.h; alpha_texels is the scene's texel
 * buffer under a second name). */
#define SCENE_GEOMETRY_PARAMS                                                                          \
  __global const BvhNode8 *restrict bvh_nodes, __global const TriangleBlock4 *restrict tri_blocks,     \
      __global const uint *restrict prim_refs, __global const Sphere *restrict spheres,                \
      __global const Cylinder *restrict cylinders, __global const Triangle *restrict triangles,       \
      __global const TriangleAlpha *restrict triangle_alpha, __global const ushort *restrict alpha_texels
#define SCENE_GEOMETRY_ARGS bvh_nodes, tri_blocks, prim_refs, spheres, cylinders, triangles, triangle_alpha, alpha_texels

CS_DEVICE Hit hit_none(float tmax) {
  Hit h;
  h.t = tmax;
  h.u = 0.0f;
  h.v = 0.0f;
  h.prim = PRIM_NONE;
  return h;
}

CS_DEVICE uint prim_ref_type(uint ref) { return ref >> PRIM_TYPE_SHIFT; }
CS_DEVICE uint prim_ref_index(uint ref) { return ref & PRIM_INDEX_MASK; }

/* Error-bounded ray origins (pbrt-v4's approach, issue 14).
 *
 * surface_at (surface.h) returns with each hit point p a conservative
 * per-component bound p_error on |p - q|, q the exact point of the surface
 * that p stands for. A new ray leaving the surface starts at
 * spawn_ray_origin(p, p_error, n, dir): p moved along the geometric normal n
 * by dot(|n|, p_error), the largest distance p can lie from the tangent
 * plane on the wrong side, toward the side dir points to, then rounded one
 * float further away. The offset therefore follows the arithmetic that made
 * p: ulp-sized for a small sphere at the origin, ~0.01 for a shape 1e5 from
 * it, tiny for a 1e-4 scene; a fixed epsilon (or one relative to |p|) is
 * too large in one of those and too small in another.
 *
 * Trade-off: the bound is conservative, so a ray may start a little farther
 * from the surface than needed; an occluder closer to the surface than the
 * offset is missed (a light leak of at most that width). The bounds below
 * are the smallest we could justify; where they also absorb the error of
 * the intersection test (triangles, see surface.h) that is said there. */

/* gamma(n) = n u / (1 - n u), u = 2^-24: the relative error bound of n
 * successive float32 roundings (Higham; pbrt's gamma). */
inline float error_gamma(float n) { return (n * 0x1.0p-24f) / (1.0f - n * 0x1.0p-24f); }

/* x moved one float toward +inf (up) or -inf (!up). Integer steps on the
 * bits: nextafter would need an infinite target, which fast-relaxed-math
 * does not allow. From zero the step goes to the least normal float, since
 * denormals may be flushed. */
inline float float_step(float x, bool up) {
  if (x == 0.0f) return up ? FLT_MIN : -FLT_MIN;
  return as_float(as_int(x) + (((x > 0.0f) == up) ? 1 : -1));
}

/* Contract: p is a computed point of a surface, p_error bounds |p - q| per
 * component for the exact surface point q, n is the surface's geometric
 * normal at p (unit, either orientation), dir the new ray's direction
 * (only its side matters: dot(dir, n) >= 0 leaves on n's side, < 0 on the
 * other; pass the side's normal itself to pick a side without a direction).
 * Returns an origin strictly on that side of the surface near p, so that a
 * ray from it with tmin = 0 does not find the surface it leaves at t ~ 0.
 * Shared by every stage that continues a path or traces a shadow or photon
 * ray from a hit. */
inline float3 spawn_ray_origin(float3 p, float3 p_error, float3 n, float3 dir) {
  const float d = dot(fabs(n), p_error);
  float3 offset = d * n;
  if (dot(dir, n) < 0.0f) offset = -offset;
  float3 po = p + offset;
  /* p + offset rounds to nearest, which may land back toward p: step once
   * more away in each component the offset moves. */
  if (offset.x != 0.0f) po.x = float_step(po.x, offset.x > 0.0f);
  if (offset.y != 0.0f) po.y = float_step(po.y, offset.y > 0.0f);
  if (offset.z != 0.0f) po.z = float_step(po.z, offset.z > 0.0f);
  return po;
}

/* Relative part of a shadow ray's margin short of its target: the target
 * distance is the norm of a difference of floats and the direction a
 * normalised vector, each a few roundings off, and the traversal finds the
 * target's own surface at a t that is itself off by its few roundings
 * (more at grazing angles). 2^-16 (about 500 roundings) covers that down to
 * grazing cosines near 0.02; an occluder within that fraction of the
 * distance from the light is missed (a light leak of 1.5e-5 of the
 * distance), the price of not letting the light's own surface shadow it. */
#define SHADOW_RAY_REL_MARGIN 0x1.0p-16f

/* tmax of a shadow ray from an origin toward a target at distance dist
 * along unit dir. The target lies on a surface with normal target_normal
 * (any orientation; zero for a point light, which is no surface) and is
 * known to within target_error per component. The ray stops short of the
 * target by the distance along dir between the two planes that bound that
 * surface there (the error along the normal over the cosine), plus the
 * relative margin above.
 *
 * Trade-off: at grazing cosines that distance grows without bound; it is
 * capped at half the segment. An occluder in the last half of a grazing
 * shadow ray is missed (a light leak), but such a sample's weight is
 * proportional to the cosine, while the light's own surface, crossed up to
 * error / cosine early, would otherwise shadow it: rectangle, triangle and
 * cylinder lights lost 1 in 1100 to 1 in 2300 of all their shadow rays,
 * every one at a cosine below 0.01, and a sphere light's rim, where the
 * crossing is a tangent, 1 in 10^5 (tests/stiff/test_shadow_rays.cpp). */
inline float shadow_ray_tmax(float dist, float3 dir, float3 target_error, float3 target_normal) {
  const float error_along_normal = dot(fabs(target_normal), target_error);
  const float cos_target = fabs(dot(dir, target_normal));
  const float short_by = error_along_normal > 0.0f
                             ? fmin(error_along_normal / fmax(cos_target, FLT_MIN), 0.5f * dist)
                             : 0.0f;
  return fmax(dist - short_by, 0.0f) * (1.0f - SHADOW_RAY_REL_MARGIN);
}

/* A shadow ray from surface point p (p_error, geometric normal n as for
 * spawn_ray_origin) to a target point (error bound target_error, surface
 * normal target_normal as for shadow_ray_tmax): returns
 * the origin, and the unit direction and tmax through *dir and *tmax
 * (pbrt-v4's SpawnRayTo).
 *
 * The direction is aimed from the offset origin, not from p. A ray from the
 * origin along the direction p -> target is that segment moved by the
 * offset; wherever the offset has a part along the target surface's normal
 * it crosses that surface short of the target, by |offset| / cos at the
 * target, which no margin proportional to the distance covers at grazing
 * angles (a floor point offset 3e-5 up reached a ceiling light 1.4e-4
 * early at cos 0.2, ten times the margin, and next-event estimation lost
 * 3.6% of that light: tests/test_path.cpp). Aimed from the origin, the ray
 * reaches the target's surface at the target itself, up to the rounding
 * of the direction that the relative margin covers. */
inline float3 spawn_ray_to(float3 p, float3 p_error, float3 n, float3 target, float3 target_error,
                           float3 target_normal, float3* dir, float* tmax) {
  const float3 origin = spawn_ray_origin(p, p_error, n, target - p);
  const float3 to_target = target - origin;
  const float dist = length(to_target);
  if (!(dist > 0.0f)) { /* target on the origin: a zero-length segment */
    *dir = n;
    *tmax = 0.0f;
    return origin;
  }
  *dir = to_target / dist;
  *tmax = shadow_ray_tmax(dist, *dir, target_error, target_normal);
  return origin;
}

#endif /* CAUSTICA_LIB_GEOMETRY_H */
