#line 2 "kernels/photon/scatter_photon_indices.cl"
/* Grid build, stage 3 of 5: each photon's index goes to its bucket's range
 * at the rank count_bucket_photons gave it. No atomics here: the ranks of a
 * bucket are distinct, so the slots are too. */

#include "lib/photon_grid.h"

__kernel void scatter_photon_indices(PhotonGridParams grid, __global const Photon* restrict photons,
                                     __global const uint* restrict bucket_start,
                                     __global const uint* restrict photon_rank,
                                     __global uint* restrict photon_index) {
  const uint i = get_global_id(0);
  if (i >= grid.photon_count) return;
  const uint bucket = photon_grid_bucket(grid, photon_grid_cell(grid, unpack3(photons[i].position)));
  photon_index[bucket_start[bucket] + photon_rank[i]] = i;
}
