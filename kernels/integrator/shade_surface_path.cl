#line 2 "kernels/integrator/shade_surface_path.cl"
/* Stage (path mode, the wavefront shape): one vertex of every path in the
 * queue (shade_path_vertex.h, whose rules hold here), its shadow ray in
 * slot i of the shadow queue, its continuation or the wave's next sample
 * pushed to the next path queue. */

#include "integrator/shade_path_vertex.h"
#include "lib/camera_sample.h"
#include "lib/queue.h"

/* The kernel: path i's vertex, then, if the path ended, the wave's next
 * sample in its place (regeneration). With count_pixel_rays (adaptive
 * sampling) each vertex counts its rays for its pixel (pixel_rays: the
 * closest-hit ray that found it, a miss included, and its shadow ray): what
 * a pixel's samples cost, which the allocation weighs. Samples and queue slots are taken
 * per work-group, one global atomic each, not per path: every path of the
 * wave would otherwise contend on the same two counters. No early return,
 * so that every work-item reaches the barriers. */
__kernel void shade_surface_path(PATH_STAGE_PARAMS, PATH_QUEUE_PARAMS(in), __global const Hit* restrict hits,
                                 PATH_QUEUE_PARAMS(next), volatile __global uint* restrict cleared_count,
                                 SHADOW_QUEUE_PARAMS(shadow), CameraGPU camera,
                                 volatile __global uint* restrict wave_progress, WAVE_ALLOCATION_PARAMS,
                                 volatile __global ulong* restrict pixel_rays, uint count_pixel_rays) {
  __local uint group_starts, group_first_sample, group_pushes, group_first_slot;
  PATH_STAGE_DATA(data);
  const uint i = get_global_id(0);
  const uint count = *in_count;
  if (i == 0) {
    *cleared_count = 0u; /* the queue iteration j + 1's shade stage pushes into */
    atomic_add(&wave_progress[WAVE_CLOSEST_RAYS], count);
  }
  if (get_local_id(0) == 0) group_starts = group_pushes = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  PathRecord child;
  bool goes_on = false, starts = false;
  if (i < count) {
    bool aux_open;
    ShadowRecord shadow_ray;
    goes_on = shade_path_vertex(&data, path_load(PATH_QUEUE_ARGS(in), i), hits[i], &shadow_ray, &child, &aux_open);
    if (shadow_ray.pixel == SHADOW_SLOT_EMPTY)
      shadow_mark_empty(SHADOW_QUEUE_ARGS(shadow), i);
    else
      shadow_store(SHADOW_QUEUE_ARGS(shadow), i, shadow_ray);
#if HAS_AUX_PASSES
    /* its path ended before a rough surface: none, once */
    if (!goes_on && aux_open)
      film_add_aux_surface(FILM_OF(&data), data.film_aux_offset, in_pixel[i], splat_float3(0.0f), splat_float3(0.0f));
#else
    (void)aux_open;
#endif
    /* its pixel's cost: the ray that found this vertex, and its shadow ray */
    if (count_pixel_rays) atom_add(&pixel_rays[in_pixel[i]], shadow_pixel[i] == SHADOW_SLOT_EMPTY ? 1ul : 2ul);
    starts = !goes_on;
  }
  const uint start_rank = starts ? atomic_inc(&group_starts) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0 && group_starts > 0u)
    group_first_sample = atomic_add(&wave_progress[WAVE_SAMPLES_STARTED], group_starts);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (starts && group_first_sample + start_rank < params.wave_samples) {
    child = camera_sample_path(&camera, &params, group_first_sample + start_rank, WAVE_ALLOCATION_ARGS);
    goes_on = true;
  }
  const uint push_rank = goes_on ? atomic_inc(&group_pushes) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0 && group_pushes > 0u) group_first_slot = atomic_add(next_count, group_pushes);
  barrier(CLK_LOCAL_MEM_FENCE);
  /* A slot past the capacity cannot happen: one record per path at most. */
  if (goes_on && group_first_slot + push_rank < params.ray_capacity)
    path_store(PATH_QUEUE_ARGS(next), group_first_slot + push_rank, child);
}
