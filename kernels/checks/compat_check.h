#line 2 "kernels/checks/compat_check.h"
/* What tests/test_compat.cpp compares between a device's OpenCL and
 * kernels/shared/compat.h on the host: the same function, compiled by each,
 * on the same inputs. It covers the builtins and operators the kernel
 * library uses (masks, select, any/all, clamp, mix, geometry, fma,
 * fmin/fmax, copysign, bit casts, floor and conversions, shuffle,
 * popcount/clz, narrowing to bytes, float8 lanes, plain arithmetic).
 * Outputs are COMPAT_CHECK_OUTPUTS floats; those before
 * COMPAT_CHECK_APPROXIMATE_FIRST must be equal (correctly rounded or exact
 * everywhere), the rest within 8 ulps (dot, cross, length, normalize,
 * mix: the order or fusion of their operations is the implementation's). */
#ifndef CAUSTICA_CHECKS_COMPAT_CHECK_H
#define CAUSTICA_CHECKS_COMPAT_CHECK_H

#include "shared/compat.h"
#include "shared/types.h"

#define COMPAT_CHECK_OUTPUTS 32
#define COMPAT_CHECK_APPROXIMATE_FIRST 24 /* outputs 24..31 may differ by up to 8 ulps */

CS_DEVICE void compat_check_values(float4 a, float4 b, float* o) {
  const float3 a3 = a.xyz, b3 = b.xyz;
  const int4 less = a < b;
  const float4 picked = select(a, b, less);
  o[0] = picked.x;
  o[1] = picked.w;
  o[2] = (float)any(less);
  o[3] = (float)all(less);
  o[4] = (float)less.y;
  const float3 clamped = clamp(a3, -0.5f, 0.5f);
  o[5] = clamped.x;
  o[6] = clamped.z;
  const float4 f = fma(a, b, splat_float4(0.5f));
  o[7] = f.y;
  o[8] = fmin(a, b).z;
  o[9] = fmax(a3, 0.25f).x;
  o[10] = copysign(splat_float3(2.0f), a3).y;
  o[11] = as_float(as_uint(a.x) ^ 0x80000000u);
  const int3 cell = convert_int3(floor(a3 * 7.0f));
  o[12] = (float)cell.x;
  o[13] = (float)cell.z;
  const float4 sh = shuffle(a, make_uint4(3u, 0u, 2u, 1u));
  o[14] = sh.x;
  o[15] = sh.w;
  o[16] = (float)popcount(as_uint(b.w));
  o[17] = (float)clz(as_uint(fabs(b.z)));
  o[18] = sqrt(fabs(a.w));
  o[19] = (float)(as_uint(convert_char4(less)) != 0u);
  const int8 m8 = splat_float8(a.x) * 2.0f - splat_float8(b.y) > splat_float8(0.0f);
  o[20] = (float)popcount(as_ulong(convert_char8(m8)) & 0x0101010101010101UL);
  o[21] = (1.0f - a.x) * (b.y / 3.0f);
  o[22] = (float)(~less).z;
  o[23] = ((a3 + b3) * 0.5f - a3 / 4.0f).y;
  /* approximate from here */
  o[24] = mix(a3, b3, 0.25f).y;
  o[25] = dot(a3, b3);
  const float3 c = cross(a3, b3);
  o[26] = c.x;
  o[27] = c.z;
  o[28] = length(a3);
  const float3 u = normalize(a3 + splat_float3(1e-3f));
  o[29] = u.x;
  o[30] = u.z;
  o[31] = dot(u, u);
}

#endif /* CAUSTICA_CHECKS_COMPAT_CHECK_H */
