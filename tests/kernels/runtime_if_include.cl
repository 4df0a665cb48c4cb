#line 2 "tests/kernels/runtime_if_include.cl"
/* tests/test_runtime.cpp's ProgramBuild.IncludesInsideIfAreDecidedByThePreprocessor:
 * the include expander honours #if. lib/optics.h is included first under
 * CONDITION (a -D of the test: 0, 1 or HAS_CAUSTICS), then unconditionally;
 * the kernel needs it either way, so the program builds and runs only if
 * the preprocessor, not the expander, decides which copy compiles. */
#if CONDITION
#include "lib/optics.h"
#endif
#include "lib/optics.h"

__kernel void k(__global float* out) {
  float cos_t;
  out[0] = fresnel_dielectric(1.0f, 1.0f / 1.5f, &cos_t);
}
