#line 2 "tests/kernels/record_layout.cl"
/* The device's side of RecordLayout (tests/test_render_core.cpp): every
 * size and offset of tests/kernels/record_layout.h as the device's
 * compiler lays the structs out, in list order. A kernel because only the
 * device's compiler can say. */
#include "shared/photon.h"
#include "shared/records.h"
#include "tests/kernels/record_layout.h"

#define DEVICE_VALUE(e) out[n++] = (uint)(e);

__kernel void layout(__global uint* out) {
  uint n = 0;
  LAYOUT_EXPRESSIONS(DEVICE_VALUE)
}
