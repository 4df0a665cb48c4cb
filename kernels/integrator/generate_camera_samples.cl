#line 2 "kernels/integrator/generate_camera_samples.cl"
/* Stage (path mode): one camera ray per pixel of the chunk for this pass's
 * sample. The pixel position is spread over the pixel (box filter) and the
 * origin over the thin lens' disk, both from the pixel's Sobol-Burley
 * sequence (dimension pairs 0 and 1), so the samples of a pixel stratify
 * its area and its lens. A ray through the lens aims at the point where the
 * pinhole ray meets the focus plane (focus distance along forward). Slot i
 * belongs to pixel pixel_offset + i; the host sets the queue count. The
 * ray's cone starts here: origin.w its width (0), dir.w its spread. */

#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/sampling.h"
#include "shared/camera.h"

__kernel void generate_camera_samples(CameraGPU camera, PathParams params, PATH_QUEUE_PARAMS(out)) {
  const uint i = get_global_id(0);
  if (i >= camera.pixel_count) return;
  const uint pixel = camera.pixel_offset + i;
  const uint pixel_seed = hash3(pixel, 0u, params.seed);
  const float2 jitter = pixel_sample_2d(params.sampler, params.sample_index, 0u, pixel_seed);
  float plane[3];
  camera_plane_point(&camera, (float)(pixel % camera.width) + jitter.x, (float)(pixel / camera.width) + jitter.y,
                     plane);
  float3 dir = normalize((float3)(plane[0], plane[1], plane[2]));
  float3 origin = camera.position.xyz;
  if (camera.lens.x > 0.0f) {
    const float3 focus = origin + dir * (camera.lens.y / dot(dir, camera.forward.xyz));
    const float2 lens =
        camera.lens.x * sample_concentric_disk(pixel_sample_2d(params.sampler, params.sample_index, 1u, pixel_seed));
    origin += lens.x * normalize(camera.right.xyz) + lens.y * normalize(camera.up.xyz);
    dir = normalize(focus - origin);
  }
  PathRecord ray = camera_path(origin, dir, pixel);
  /* The ray cone (shade_surface_path): no width at the camera, spreading by
   * the angle one pixel subtends (up is scaled by tan(fov / 2)). */
  ray.dir.w = 2.0f * length(camera.up.xyz) / (float)camera.height;
  path_store(PATH_QUEUE_ARGS(out), i, ray);
}
