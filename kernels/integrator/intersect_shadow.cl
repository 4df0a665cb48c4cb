#line 2 "kernels/integrator/intersect_shadow.cl"
/* Stage 4: any-hit occlusion test for every shadow ray; an unoccluded ray
 * adds its precomputed light contribution to its pixel. The segment ends
 * just short of the light (tmax is stored in origin.w by the shader). */

#include "lib/bvh_traverse.h"
#include "lib/film.h"
#include "lib/queue.h"

__kernel void intersect_shadow(SCENE_GEOMETRY_PARAMS, __global const uint* restrict shadow_count,
                               SHADOW_QUEUE_PARAMS(shadow), __global ulong* restrict film) {
  const uint i = get_global_id(0);
  if (i >= *shadow_count) return;
  const float4 origin = shadow_origin[i];
  if (trace_any(SCENE_GEOMETRY_ARGS, origin.xyz, shadow_dir[i].xyz, 0.0f, origin.w)) return;
  film_add(film, shadow_pixel[i], shadow_contribution[i].xyz);
}
