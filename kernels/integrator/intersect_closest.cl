#line 2 "kernels/integrator/intersect_closest.cl"
/* Stage 2: closest hit for every ray in the queue. Writes one hit record per
 * queue slot: (t, u, v, prim bits); prim == PRIM_NONE marks a miss. */

#include "lib/bvh_traverse.h"
#include "lib/queue.h"

__kernel void intersect_closest(SCENE_GEOMETRY_PARAMS, __global const uint* restrict ray_count,
                                __global const float4* restrict ray_origin,
                                __global const float4* restrict ray_dir, __global float4* restrict hits) {
  const uint i = get_global_id(0);
  if (i >= *ray_count) return;
  const Hit hit = trace_closest(SCENE_GEOMETRY_ARGS, ray_origin[i].xyz, ray_dir[i].xyz, 0.0f, 1e30f);
  hits[i] = (float4)(hit.t, hit.u, hit.v, as_float(hit.prim));
}
