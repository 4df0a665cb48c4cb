#line 2 "kernels/integrator/trace_paths.cl"
/* The path tracer's CPU shape (issue 39, `--kernel-shape paths`): the same
 * stage functions as the wavefront (camera_sample_path, trace_closest,
 * shade_path_vertex, trace_any, the film's adds), called in one kernel.
 * Each work-item takes the wave's next sample, carries its path from the
 * camera to its end with the path in registers (no queues, no records in
 * memory), traces each vertex's shadow ray at once, and takes the next
 * sample until the wave's are all started: one launch per wave.
 *
 * Rules: a sample is the same path in both shapes (its index picks its
 * pixel and its random numbers, never its slot or work-item), and the film
 * sums in fixed point, so both shapes give the same bits; the counters the
 * wavefront keeps (closest-hit rays, shadow rays traced, the pixels' ray
 * counts) are kept alike. The host zeroes WAVE_SAMPLES_STARTED before the
 * launch. No barriers: work-items run apart, as many as the device has
 * threads for (a CPU runs a work-group's items one after another). */

#include "integrator/shade_path_vertex.h"
#include "lib/bvh_traverse.h"
#include "lib/camera_sample.h"

__kernel void trace_paths(PATH_STAGE_PARAMS, volatile __global uint* restrict traced, CameraGPU camera,
                          volatile __global uint* restrict wave_progress, WAVE_ALLOCATION_PARAMS,
                          volatile __global ulong* restrict pixel_rays, uint count_pixel_rays) {
  PATH_STAGE_DATA(data);
  uint closest_rays = 0u, shadow_rays = 0u;
  for (;;) {
    const uint sample = atomic_inc(&wave_progress[WAVE_SAMPLES_STARTED]);
    if (sample >= params.wave_samples) break;
    PathRecord ray = camera_sample_path(&camera, &data.params, sample, WAVE_ALLOCATION_ARGS);
    for (;;) {
      const Hit hit = trace_closest(SCENE_GEOMETRY_OF(&data.scene), ray.origin.xyz, ray.dir.xyz, 0.0f, RAY_T_FAR);
      ++closest_rays;
      ShadowRecord shadow;
      PathRecord child;
      bool aux_open;
      const bool goes_on = shade_path_vertex(&data, ray, hit, &shadow, &child, &aux_open);
#if HAS_AUX_PASSES
      /* its path ended before a rough surface: none, once */
      if (!goes_on && aux_open)
        film_add_aux_surface(FILM_OF(&data), data.film_aux_offset, ray.pixel, splat_float3(0.0f), splat_float3(0.0f));
#else
      (void)aux_open;
#endif
      const bool has_shadow = shadow.pixel != SHADOW_SLOT_EMPTY;
      if (has_shadow) {
        ++shadow_rays;
        if (!trace_any(SCENE_GEOMETRY_OF(&data.scene), shadow.origin.xyz, shadow.dir.xyz, 0.0f, shadow.tmax))
          film_add(FILM_OF(&data), shadow.pixel, shadow.contribution.xyz);
      }
      /* its pixel's cost: the ray that found this vertex, and its shadow ray */
      if (count_pixel_rays) atom_add(&pixel_rays[ray.pixel], has_shadow ? 2ul : 1ul);
      if (!goes_on) break;
      ray = child;
    }
  }
  if (closest_rays > 0u) atomic_add(&wave_progress[WAVE_CLOSEST_RAYS], closest_rays);
  if (shadow_rays > 0u) atomic_add(traced, shadow_rays);
}
