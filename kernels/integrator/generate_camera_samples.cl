#line 2 "kernels/integrator/generate_camera_samples.cl"
/* Stage (path mode): starts a wave. Slot i gets the camera path of wave
 * sample i (lib/camera_sample.h) for the first min(wave samples, slots);
 * the shade stage starts the rest as paths end. Work-item 0 also sets the
 * wave's counters (shared/types.h): the first iteration's queue holds those
 * paths, the queue it pushes into is empty, nothing is counted yet, so the
 * host writes nothing between waves. */

#include "lib/camera_sample.h"

__kernel void generate_camera_samples(CameraGPU camera, PathParams params, PATH_QUEUE_PARAMS(out),
                                      __global uint* restrict next_count, __global uint* restrict wave_progress,
                                      WAVE_ALLOCATION_PARAMS) {
  const uint i = get_global_id(0);
  const uint started = min(params.wave_samples, params.ray_capacity);
  if (i == 0) {
    *out_count = started;
    *next_count = 0u;
    wave_progress[WAVE_SAMPLES_STARTED] = started;
  }
  if (i >= started) return;
  path_store(PATH_QUEUE_ARGS(out), i, camera_sample_path(&camera, &params, i, WAVE_ALLOCATION_ARGS));
}
