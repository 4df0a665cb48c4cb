#line 2 "kernels/integrator/intersect_shadow.cl"
/* Stage: any-hit occlusion test for every shadow ray; an unoccluded ray
 * adds its precomputed contribution to its pixel. The segment ends just
 * short of the light (tmax in origin.w, set by the shade stage). */

#include "lib/bvh_traverse.h"
#include "lib/film.h"
#include "lib/queue.h"

__kernel void intersect_shadow(SCENE_GEOMETRY_PARAMS, SHADOW_QUEUE_PARAMS(shadow), FILM_PARAMS) {
  const uint i = get_global_id(0);
  if (i >= *shadow_count) return;
  const ShadowRecord ray = shadow_load(SHADOW_QUEUE_ARGS(shadow), i);
  if (trace_any(SCENE_GEOMETRY_ARGS, ray.origin.xyz, ray.dir.xyz, 0.0f, ray.origin.w)) return;
  film_add(FILM_ARGS, ray.pixel, ray.contribution.xyz);
}
