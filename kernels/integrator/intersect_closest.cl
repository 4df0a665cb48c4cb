#line 2 "kernels/integrator/intersect_closest.cl"
/* Stage: closest hit for every ray of a queue, one Hit per queue slot
 * (prim == PRIM_NONE marks a miss). Reads only the rays' origins and
 * directions, so any ray queue can be traced, and the benchmark traces its
 * own ray sets with this very kernel. */

#include "lib/bvh_traverse.h"
#include "lib/queue.h"

__kernel void intersect_closest(SCENE_GEOMETRY_PARAMS, RAY_VIEW_PARAMS(rays), __global Hit* restrict hits) {
  const uint i = get_global_id(0);
  if (i >= *rays_count) return;
  hits[i] = trace_closest(SCENE_GEOMETRY_ARGS, rays_origin[i].xyz, rays_dir[i].xyz, 0.0f, RAY_T_FAR);
}
