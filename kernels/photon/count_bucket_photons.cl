#line 2 "kernels/photon/count_bucket_photons.cl"
/* Grid build, stage 1 of 5: each photon's bucket gets one atomic increment
 * in bucket_start (zeroed by the host; scan_bucket_counts turns the counts
 * into starts in place). The value the increment returns, the photon's rank
 * among its bucket's photons in arrival order, is kept for the scatter: that
 * order depends on the threads, and sort_bucket_photons replaces it by the
 * photons' index order afterwards. */

#include "lib/photon_grid.h"

__kernel void count_bucket_photons(PhotonGridParams grid, __global const Photon* restrict photons,
                                   volatile __global uint* restrict bucket_start,
                                   __global uint* restrict photon_rank) {
  const uint i = get_global_id(0);
  if (i >= grid.photon_count) return;
  const uint bucket = photon_grid_bucket(grid, photon_grid_cell(grid, unpack3(photons[i].position)));
  photon_rank[i] = atomic_inc(&bucket_start[bucket]);
}
