#line 2 "kernels/photon/scan_bucket_counts.cl"
/* Grid build, stage 2 of 5: the exclusive prefix sum of the bucket counts,
 * in place (bucket b's photons then start at bucket_start[b]; the extra last
 * entry becomes the total). Work-item g owns the PHOTON_SCAN_BLOCK
 * consecutive values from g * PHOTON_SCAN_BLOCK and walks them serially:
 * sum_scan_blocks writes each block's sum, the host scans those sums the
 * same way (recursively, down to a single block whose offset is 0), and
 * scan_blocks_exclusive rewrites each block as its offset plus a running
 * sum. No local memory and no barriers, so any work-group size and any
 * device gives the same (integer, exact) answer; 2^22 buckets take three
 * levels. */

#include "shared/photon.h"

__kernel void sum_scan_blocks(__global const uint* restrict values, uint value_count,
                              __global uint* restrict block_sums) {
  const uint block = get_global_id(0);
  const uint first = block * PHOTON_SCAN_BLOCK;
  if (first >= value_count) return;
  const uint end = min(first + PHOTON_SCAN_BLOCK, value_count);
  uint sum = 0u;
  for (uint i = first; i < end; ++i) sum += values[i];
  block_sums[block] = sum;
}

__kernel void scan_blocks_exclusive(__global uint* restrict values, uint value_count,
                                    __global const uint* restrict block_offsets) {
  const uint block = get_global_id(0);
  const uint first = block * PHOTON_SCAN_BLOCK;
  if (first >= value_count) return;
  const uint end = min(first + PHOTON_SCAN_BLOCK, value_count);
  uint running = block_offsets[block];
  for (uint i = first; i < end; ++i) {
    const uint value = values[i];
    values[i] = running;
    running += value;
  }
}
