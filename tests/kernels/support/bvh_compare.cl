#line 2 "tests/kernels/support/bvh_compare.cl"
/* tests/support/bvh_compare.cpp's device side: per ray, the BVH's closest
 * hit (trace_closest), a brute-force closest hit over every primitive and
 * the any-hit answer (trace_any). A kernel because what is compared is the
 * device traversal (its stack, its 8-wide slab tests, the prefetching CPU
 * path) under both the renderer's -cl-fast-relaxed-math and strict builds. */
#include "lib/bvh_traverse.h"

__kernel void compare(SCENE_GEOMETRY_PARAMS, __global const uint* all_refs, uint prim_count,
                      __global const float4* rays, uint ray_count, __global float4* out) {
  uint i = get_global_id(0);
  if (i >= ray_count) return;
  float4 o = rays[2 * i], d = rays[2 * i + 1]; /* o.w = tmin, d.w = tmax of the any-hit query */
  Hit bvh = trace_closest(SCENE_GEOMETRY_ARGS, o.xyz, d.xyz, o.w, RAY_T_FAR);
  Hit brute = hit_none(RAY_T_FAR);
  for (uint p = 0; p < prim_count; ++p)
    intersect_prim_ref(spheres, cylinders, triangles, all_refs[p], o.xyz, d.xyz, o.w, &brute);
  bool any = trace_any(SCENE_GEOMETRY_ARGS, o.xyz, d.xyz, o.w, d.w);
  out[i] = (float4)(bvh.t, as_float(bvh.prim), brute.t, as_float(brute.prim));
  out[ray_count + i] = (float4)(any ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f);
}
