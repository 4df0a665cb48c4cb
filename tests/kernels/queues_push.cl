#line 2 "tests/kernels/queues_push.cl"
/* tests/test_queues.cpp's device side: work-item i pushes (i % 4) entries
 * through queue_reserve (lib/queue.h), each tagged with (i << 2) | k. A
 * kernel because what is tested is the atomic counter under many
 * work-items at once: distinct slots, and overflow dropped in bounds. */
#include "lib/queue.h"
__kernel void push_test(volatile __global uint* count, uint capacity, __global uint* slots, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  for (uint k = 0; k < i % 4; ++k) {
    const uint slot = queue_reserve(count, capacity);
    if (slot != 0xFFFFFFFFu) slots[slot] = (i << 2) | k;
  }
}
