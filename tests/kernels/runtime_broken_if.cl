#line 2 "tests/kernels/runtime_broken_if.cl"
/* tests/test_runtime.cpp: a build error after an include inside a false
 * #if and the same include outside it; the log must still name this
 * file's line of the error (line 11). Keep it there or update the test. */
#if 0
#include "lib/optics.h"
#endif
#include "lib/optics.h"
__kernel void k(__global float* x) {
  /* declared nowhere: */
  x[0] = undefined_name;
}
