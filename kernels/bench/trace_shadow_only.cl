#line 2 "kernels/bench/trace_shadow_only.cl"
/* Bench only (caustica bench): intersect_shadow's any-hit traversal without
 * its film update, so that shadow-ray throughput measures traversal rather
 * than atomics, and the answer per ray can be checked against the host
 * trace. Same ray view as intersect_closest (host/bench/ray_batch.h), with
 * tmax in origin.w (the bench's RayBatch, not a queue record); writes 1 for an occluded segment,
 * 0 for a clear one. */

#include "lib/bvh_traverse.h"
#include "lib/queue.h"

__kernel void trace_shadow_only(SCENE_GEOMETRY_PARAMS, RAY_VIEW_PARAMS(rays), __global uint* restrict occluded) {
  const uint i = get_global_id(0);
  if (i >= *rays_count) return;
  const float4 origin = rays_origin[i];
  occluded[i] = trace_any(SCENE_GEOMETRY_ARGS, origin.xyz, rays_dir[i].xyz, 0.0f, origin.w) ? 1u : 0u;
}
