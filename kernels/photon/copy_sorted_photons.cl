#line 2 "kernels/photon/copy_sorted_photons.cl"
/* Grid build, stage 5 of 5: the photons themselves in bucket order, so a
 * query reads each bucket's photons from consecutive memory. */

#include "shared/photon.h"

__kernel void copy_sorted_photons(PhotonGridParams grid, __global const Photon* restrict photons,
                                  __global const uint* restrict photon_index,
                                  __global Photon* restrict grid_photons) {
  const uint slot = get_global_id(0);
  if (slot >= grid.photon_count) return;
  grid_photons[slot] = photons[photon_index[slot]];
}
