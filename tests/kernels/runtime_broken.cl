#line 2 "tests/kernels/runtime_broken.cl"
/* tests/test_runtime.cpp's ProgramBuild.FailureCarriesTheLogAtTheOriginalLine:
 * a kernel that does not build, after an include, so that the build log
 * must point at this file's line of the error (line 9) through the #line
 * markers. Keep the error on line 9 or update the test. */
#include "shared/types.h"
__kernel void k(__global float* x) {
  /* the name below is declared nowhere: */
  x[0] = undefined_name;
}
