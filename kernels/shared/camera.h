#line 2 "kernels/shared/camera.h"
/* The camera model, compiled by both sides: the renderer's
 * generate_camera_rays stage and the host's benchmark rays
 * (host/bench/bench_rays.cpp) call this one function, so the two cannot
 * drift apart. The host fills CameraGPU with camera_for_image
 * (host/scene/scene.h).
 *
 * Pinhole: the image-plane point of (px, py) in pixels from the top-left
 * corner is forward + sx * right + sy * up with sx = 2 px / W - 1,
 * sy = 1 - 2 py / H, where right and up are pre-scaled by tan(fov/2) * aspect
 * and tan(fov/2). Each component is two fused multiply-adds written out, so
 * both compilers round the same way; the caller normalises (OpenCL's
 * normalize on the device, v / sqrt(v.v) on the host). */
#ifndef CAUSTICA_SHARED_CAMERA_H
#define CAUSTICA_SHARED_CAMERA_H

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#define CS_FMA(a, b, c) fma(a, b, c)
#else
#include "kernels/shared/types.h"
#define CS_FMA(a, b, c) __builtin_fmaf(a, b, c)
#endif

/* Unnormalised direction through (px, py) of the image plane. */
static inline void camera_plane_point(const CameraGPU* camera, float px, float py, float out[3]) {
  const float sx = 2.0f * px / (float)camera->width - 1.0f;
  const float sy = 1.0f - 2.0f * py / (float)camera->height;
  out[0] = CS_FMA(sy, camera->up.x, CS_FMA(sx, camera->right.x, camera->forward.x));
  out[1] = CS_FMA(sy, camera->up.y, CS_FMA(sx, camera->right.y, camera->forward.y));
  out[2] = CS_FMA(sy, camera->up.z, CS_FMA(sx, camera->right.z, camera->forward.z));
}

/* Through the centre of pixel `pixel` (row-major index in the whole image). */
static inline void camera_pixel_centre_point(const CameraGPU* camera, cs_uint pixel, float out[3]) {
  camera_plane_point(camera, (float)(pixel % camera->width) + 0.5f, (float)(pixel / camera->width) + 0.5f, out);
}

#endif /* CAUSTICA_SHARED_CAMERA_H */
