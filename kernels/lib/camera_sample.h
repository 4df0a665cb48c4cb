#line 2 "kernels/lib/camera_sample.h"
/* A camera path for one sample of the path tracer's wave: the stage that
 * starts a wave (generate_camera_samples) and the shade stage, which starts
 * the wave's next sample in the slot of a path that ended (path
 * regeneration), call this one function.
 *
 * Rules: wave sample s is a pixel and an index into that pixel's sample
 * sequence (lib/wave_samples.h: alike for every pixel, or from the film's
 * list of an adaptive wave), whatever slot or order traces it. The pixel position is spread
 * over the pixel (box filter) and the origin over the thin lens' disk, both
 * from the pixel's Sobol-Burley sequence (dimension pairs 0 and 1), so the
 * samples of a pixel stratify its area and its lens. A ray through the lens
 * aims at the point where the pinhole ray meets the focus plane (focus
 * distance along forward). The ray's cone starts here: cone_width 0,
 * cone_spread the angle one pixel subtends (up is scaled by tan(fov / 2)). */
#ifndef CAUSTICA_LIB_CAMERA_SAMPLE_H
#define CAUSTICA_LIB_CAMERA_SAMPLE_H

#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/sampling.h"
#include "lib/wave_samples.h"
#include "shared/camera.h"

inline PathRecord camera_sample_path(const CameraGPU* camera, const PathParams* params, uint wave_sample,
                                     WAVE_ALLOCATION_PARAMS) {
  uint pixel;
  const uint sample = wave_sample_index(params, camera->pixel_offset, wave_sample, WAVE_ALLOCATION_ARGS, &pixel);
  const uint pixel_seed = hash3(pixel, 0u, params->seed);
  const float2 jitter = pixel_sample_2d(params->sampler, sample, 0u, pixel_seed);
  float plane[3];
  camera_plane_point(camera, (float)(pixel % camera->width) + jitter.x, (float)(pixel / camera->width) + jitter.y,
                     plane);
  float3 dir = normalize((float3)(plane[0], plane[1], plane[2]));
  float3 origin = camera->position.xyz;
  if (camera->lens.x > 0.0f) {
    const float3 focus = origin + dir * (camera->lens.y / dot(dir, camera->forward.xyz));
    const float2 lens = camera->lens.x * sample_concentric_disk(pixel_sample_2d(params->sampler, sample, 1u, pixel_seed));
    origin += lens.x * normalize(camera->right.xyz) + lens.y * normalize(camera->up.xyz);
    dir = normalize(focus - origin);
  }
  PathRecord ray = camera_path(origin, dir, pixel, sample);
  ray.cone_spread = 2.0f * length(camera->up.xyz) / (float)camera->height;
#if HAS_AUX_PASSES
  ray.flags |= PATH_AUX_PENDING;
#endif
  return ray;
}

#endif
