#line 2 "kernels/checks/compat_check.cl"
/* tests/test_compat.cpp's device side: compat_check_values for every input
 * pair. Not part of any renderer program. */

/* No contraction, as the host builds it: the check is of the mapping, not
 * of the compilers' fusing (the renderer lets the device fuse). */
#pragma OPENCL FP_CONTRACT OFF

#include "checks/compat_check.h"

__kernel void compat_check(__global const float4* a_in, __global const float4* b_in, uint n, __global float* out) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  float o[COMPAT_CHECK_OUTPUTS];
  compat_check_values(a_in[i], b_in[i], o);
  for (uint k = 0; k < COMPAT_CHECK_OUTPUTS; ++k) out[COMPAT_CHECK_OUTPUTS * i + k] = o[k];
}
