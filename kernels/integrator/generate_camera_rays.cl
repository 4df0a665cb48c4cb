#line 2 "kernels/integrator/generate_camera_rays.cl"
/* Stage: one primary ray per pixel of the current chunk, through the pixel
 * centre (binary and phong sample the centre, as the coursework does).
 * Slot i of the queue belongs to pixel pixel_offset + i, so this stage needs
 * no atomics; work-item 0 sets the queue count to the chunk size and
 * empties the queue the first shade stage pushes into (next_count), so the
 * host writes nothing (host/render/wave_loop.h). */

#include "lib/queue.h"
#include "shared/camera.h"

__kernel void generate_camera_rays(CameraGPU camera, PATH_QUEUE_PARAMS(out), __global uint* restrict next_count) {
  const uint i = get_global_id(0);
  if (i == 0) {
    *out_count = camera.pixel_count;
    *next_count = 0u;
  }
  if (i >= camera.pixel_count) return;
  const uint pixel = camera.pixel_offset + i;
  float plane[3];
  camera_pixel_centre_point(&camera, pixel, plane);
  path_store(PATH_QUEUE_ARGS(out), i,
             camera_path(camera.position.xyz, normalize((float3)(plane[0], plane[1], plane[2])), pixel, 0u));
}
