#line 2 "tests/kernels/textures_sample.cl"
/* tests/test_textures.cpp's texture_lookup queries: per lookup the texture
 * index and uv, the rgb sampled. A kernel because the texels are halfs read
 * by vload_half, and the test runs the device build under the renderer's
 * -cl-fast-relaxed-math and without. */
#include "lib/texture.h"

__kernel void sample(__global const Texture* textures, __global const half* texels, __global const int* index,
                     __global const float2* uv, uint count, __global float4* out) {
  uint i = get_global_id(0);
  if (i >= count) return;
  out[i] = (float4)(texture_lookup(textures, texels, index[i], uv[i]), 0.0f);
}
