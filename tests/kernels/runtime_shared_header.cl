#line 2 "tests/kernels/runtime_shared_header.cl"
/* tests/test_runtime.cpp: a shared header's C++ side is known dead, so its
 * includes are dropped (they need not be kernel files), and its OpenCL
 * side counts as unconditional. */
#ifdef __OPENCL_C_VERSION__
#include "lib/optics.h"
#else
#include "host/not_a_kernel.h"
#endif

__kernel void k(__global float* out) {
  float cos_t;
  out[0] = fresnel_dielectric(1.0f, 1.0f / 1.5f, &cos_t);
}
