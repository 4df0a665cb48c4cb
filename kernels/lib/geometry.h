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
 * refs of the sphere/cylinder leaves) and the primitive arrays. */
#define SCENE_GEOMETRY_PARAMS                                                                          \
  __global const BvhNode8 *restrict bvh_nodes, __global const TriangleBlock4 *restrict tri_blocks,     \
      __global const uint *restrict prim_refs, __global const Sphere *restrict spheres,                \
      __global const Cylinder *restrict cylinders, __global const Triangle *restrict triangles
#define SCENE_GEOMETRY_ARGS bvh_nodes, tri_blocks, prim_refs, spheres, cylinders, triangles

Hit hit_none(float tmax) {
  Hit h;
  h.t = tmax;
  h.u = 0.0f;
  h.v = 0.0f;
  h.prim = PRIM_NONE;
  return h;
}

uint prim_ref_type(uint ref) { return ref >> PRIM_TYPE_SHIFT; }
uint prim_ref_index(uint ref) { return ref & PRIM_INDEX_MASK; }

/* Spawn point for a secondary ray leaving a surface at p on the side n points
 * to. Intersection and re-projection errors grow with |p|, so a fixed epsilon
 * is either too small at 1e4 or too large at 1e-3; instead each component is
 * pushed a fixed number of ULPs (integer arithmetic on the float bits), and
 * only components too close to zero for ULPs to mean anything get a tiny
 * absolute push. */
#define OFFSET_ABS_THRESHOLD (1.0f / 32.0f)
#define OFFSET_ABS_SCALE (1.0f / 65536.0f)
#define OFFSET_ULP_SCALE 256.0f

float offset_component(float p, float n) {
  if (fabs(p) < OFFSET_ABS_THRESHOLD) return p + OFFSET_ABS_SCALE * n;
  int ulps = (int)(OFFSET_ULP_SCALE * n);
  /* Adding to the bit pattern moves away from zero; negative p needs the
   * opposite sign to move in the direction of n. */
  return as_float(as_int(p) + (p < 0.0f ? -ulps : ulps));
}

float3 offset_ray_origin(float3 p, float3 n) {
  return (float3)(offset_component(p.x, n.x), offset_component(p.y, n.y), offset_component(p.z, n.z));
}

#endif /* CAUSTICA_LIB_GEOMETRY_H */
