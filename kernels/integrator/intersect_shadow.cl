#line 2 "kernels/integrator/intersect_shadow.cl"
/* Stage: any-hit occlusion test for every shadow slot; empty slots are
 * skipped, an unoccluded ray adds its precomputed contribution to its pixel.
 * The segment ends just short of the light (its tmax, set by the shade
 * stage). The rays actually traced are counted per work-group and
 * added to *traced with one atomic, for the host's statistics: a global
 * atomic per ray would contend on one cache line. No early return, so that
 * every work-item reaches the barriers. */

#include "lib/bvh_traverse.h"
#include "lib/film.h"
#include "lib/queue.h"

__kernel void intersect_shadow(SCENE_GEOMETRY_PARAMS, SHADOW_QUEUE_PARAMS(shadow), FILM_PARAMS,
                               volatile __global uint* restrict traced) {
  __local uint group_traced;
  const uint i = get_global_id(0);
  if (get_local_id(0) == 0) group_traced = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (i < *shadow_count && shadow_pixel[i] != SHADOW_SLOT_EMPTY) {
    const ShadowRecord ray = shadow_load(SHADOW_QUEUE_ARGS(shadow), i);
    atomic_inc(&group_traced);
    if (!trace_any(SCENE_GEOMETRY_ARGS, ray.origin.xyz, ray.dir.xyz, 0.0f, ray.tmax))
      film_add(FILM_ARGS, ray.pixel, ray.contribution.xyz);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0 && group_traced > 0) atomic_add(traced, group_traced);
}
