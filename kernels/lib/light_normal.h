#line 2 "kernels/lib/light_normal.h"
/* The normal a path carries for the light tree (PathRecord.light_normal,
 * lib/light_pick.h): packed in one 32-bit word, so that the queues move 4
 * bytes for it rather than 16. Compiled as C++ too (host tests). */
#ifndef CAUSTICA_LIB_LIGHT_NORMAL_H
#define CAUSTICA_LIB_LIGHT_NORMAL_H

#ifdef __OPENCL_C_VERSION__
#include "shared/records.h"
#else
#include "kernels/shared/compat.h"
#include "kernels/shared/records.h"
#endif

/* A unit normal packed in 32 bits: the octahedral map (Meyer et al. 2010,
 * "On Floating-Point Normal Vectors"), 16 bits a coordinate, quantised to
 * 0..65534 so that no packed normal is LIGHT_NORMAL_NONE. About 5e-5
 * radians apart at worst: the tree's normal term gives 1e-3 radians of
 * slack (light_tree_importance). */
inline uint light_normal_pack(float3 n) {
  const float l1 = fabs(n.x) + fabs(n.y) + fabs(n.z);
  float x = n.x / l1, y = n.y / l1;
  if (n.z < 0.0f) {
    const float fx = (1.0f - fabs(y)) * copysign(1.0f, x), fy = (1.0f - fabs(x)) * copysign(1.0f, y);
    x = fx;
    y = fy;
  }
  const uint qx = (uint)(clamp(x * 0.5f + 0.5f, 0.0f, 1.0f) * 65534.0f + 0.5f);
  const uint qy = (uint)(clamp(y * 0.5f + 0.5f, 0.0f, 1.0f) * 65534.0f + 0.5f);
  return qx | (qy << 16);
}

/* The normal light_normal_pack packed (unit length); zero for
 * LIGHT_NORMAL_NONE, which asks the tree for no normal term. */
inline float3 light_normal_unpack(uint packed) {
  if (packed == LIGHT_NORMAL_NONE) return make_float3(0.0f, 0.0f, 0.0f);
  float x = (float)(packed & 0xFFFFu) * (2.0f / 65534.0f) - 1.0f;
  float y = (float)(packed >> 16) * (2.0f / 65534.0f) - 1.0f;
  const float z = 1.0f - fabs(x) - fabs(y);
  if (z < 0.0f) {
    const float fx = (1.0f - fabs(y)) * copysign(1.0f, x), fy = (1.0f - fabs(x)) * copysign(1.0f, y);
    x = fx;
    y = fy;
  }
  return normalize(make_float3(x, y, z));
}

#endif
