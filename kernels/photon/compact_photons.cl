#line 2 "kernels/photon/compact_photons.cl"
/* Stage (photon pass): the stored photons, packed in photon order.
 *
 * Rules: `offsets` is the exclusive prefix sum of bounce_photons' `stored`
 * flags (one per photon path, plus a last entry that becomes the total), so
 * photon path i, when it stored one, writes slot offsets[i]: the packed
 * array depends only on the photons, never on the order of the queues. */

#include "shared/photon.h"

__kernel void compact_photons(__global const Photon* restrict candidates, __global const uint* restrict stored,
                              __global const uint* restrict offsets, uint photon_count,
                              __global Photon* restrict photons) {
  const uint i = get_global_id(0);
  if (i >= photon_count || !stored[i]) return;
  photons[offsets[i]] = candidates[i];
}
