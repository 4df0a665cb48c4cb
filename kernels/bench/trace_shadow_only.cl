#line 2 "kernels/bench/trace_shadow_only.cl"
/* Bench only (caustica bench): intersect_shadow's any-hit traversal without
 * its film update, so that shadow-ray throughput measures traversal rather
 * than atomics, and the answer per ray can be checked against the host
 * trace. Same ray layout as the shadow queue: tmax in origin.w. Same
 * argument shape as intersect_closest (WavefrontRenderer::time_ray_kernel);
 * writes 1 for an occluded segment, 0 for a clear one. */

#include "lib/bvh_traverse.h"

__kernel void trace_shadow_only(SCENE_GEOMETRY_PARAMS, __global const uint* restrict ray_count,
                                __global const float4* restrict ray_origin, __global const float4* restrict ray_dir,
                                __global uint* restrict occluded) {
  const uint i = get_global_id(0);
  if (i >= *ray_count) return;
  const float4 origin = ray_origin[i];
  occluded[i] = trace_any(SCENE_GEOMETRY_ARGS, origin.xyz, ray_dir[i].xyz, 0.0f, origin.w) ? 1u : 0u;
}
