#line 2 "kernels/photon/sort_bucket_photons.cl"
/* Grid build, stage 4 of 5: one work-item per bucket sorts its photon
 * indices ascending, replacing the thread-dependent arrival order of the
 * scatter, so the grid (and every sum a gather makes in bucket order) is the
 * same bits for any thread count or work-group size. Buckets hold about one
 * photon (table_size >= 2 x photons) and get an insertion sort; a bright
 * caustic can pile thousands into one cell, so longer buckets are
 * heap-sorted (in place, n log n, no recursion). */

#include "shared/photon.h"

#define SORT_INSERTION_MAX 16u

inline void sort_indices_insertion(__global uint* a, uint n) {
  for (uint i = 1u; i < n; ++i) {
    const uint value = a[i];
    uint j = i;
    for (; j > 0u && a[j - 1u] > value; --j) a[j] = a[j - 1u];
    a[j] = value;
  }
}

/* Moves a[root] down the max-heap a[0, n) to where it belongs. */
inline void sift_down(__global uint* a, uint root, uint n) {
  const uint value = a[root];
  for (;;) {
    uint child = 2u * root + 1u;
    if (child >= n) break;
    if (child + 1u < n && a[child + 1u] > a[child]) ++child;
    if (a[child] <= value) break;
    a[root] = a[child];
    root = child;
  }
  a[root] = value;
}

inline void sort_indices_heap(__global uint* a, uint n) {
  for (uint root = n / 2u; root-- > 0u;) sift_down(a, root, n);
  for (uint end = n - 1u; end > 0u; --end) {
    const uint top = a[0];
    a[0] = a[end];
    a[end] = top;
    sift_down(a, 0u, end);
  }
}

__kernel void sort_bucket_photons(PhotonGridParams grid, __global const uint* restrict bucket_start,
                                  __global uint* restrict photon_index) {
  const uint bucket = get_global_id(0);
  if (bucket >= grid.table_size) return;
  const uint first = bucket_start[bucket];
  const uint n = bucket_start[bucket + 1u] - first;
  if (n <= SORT_INSERTION_MAX)
    sort_indices_insertion(photon_index + first, n);
  else
    sort_indices_heap(photon_index + first, n);
}
