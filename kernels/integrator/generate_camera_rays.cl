#line 2 "kernels/integrator/generate_camera_rays.cl"
/* Stage 1: one primary ray per pixel of the current chunk, through the pixel
 * centre (binary and phong modes sample the centre, as the coursework does).
 * Slot i of the queue belongs to pixel chunk_start + i, so this stage needs
 * no atomics; the host sets the queue count to the chunk size. */

#include "lib/queue.h"

__kernel void generate_camera_rays(CameraGPU camera, RAY_QUEUE_PARAMS(out)) {
  const uint i = get_global_id(0);
  if (i >= camera.pixel_count) return;
  const uint pixel = camera.pixel_offset + i;
  const float px = (float)(pixel % camera.width) + 0.5f;
  const float py = (float)(pixel / camera.width) + 0.5f;
  const float sx = 2.0f * px / (float)camera.width - 1.0f;
  const float sy = 1.0f - 2.0f * py / (float)camera.height;
  const float3 dir = normalize(camera.forward.xyz + sx * camera.right.xyz + sy * camera.up.xyz);
  out_origin[i] = (float4)(camera.position.xyz, 0.0f);
  out_dir[i] = (float4)(dir, 0.0f);
  out_weight[i] = (float4)(1.0f, 1.0f, 1.0f, as_float(0u));
  out_pixel[i] = pixel;
}
