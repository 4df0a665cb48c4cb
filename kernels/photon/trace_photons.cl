#line 2 "kernels/photon/trace_photons.cl"
/* The photon pass's CPU shape (issue 39, `--kernel-shape paths`): a photon
 * is a path from a light. Each work-item takes this process's next photon,
 * emits it (emit_photon), follows it through trace_closest and
 * bounce_photon until it is stored or ends, and takes the next: one launch
 * per photon map, the photon in registers.
 *
 * Rules: as the wavefront's stages (emit_photons.cl, bounce_photons.cl),
 * whose functions these are: photon i's random numbers are keyed by i and
 * a stored photon goes to slot i of `candidates` (flag 1 in `stored`), so
 * the compaction that follows makes the same photon map, bit for bit,
 * whatever order the work-items ran in. progress[0] counts the photons
 * taken (the host zeroes it before the launch), progress[1] the rays
 * traced, over the render (modulo 2^32) as the wavefront's counter. */

#include "lib/bvh_traverse.h"

__kernel void trace_photons(SCENE_BUFFERS_PARAMS, PhotonPassParams params,
                            __global const float4* restrict casters, uint caster_count,
                            __global Photon* restrict candidates, __global uint* restrict stored,
                            volatile __global uint* restrict progress) {
  const SceneBuffers scene = SCENE_BUFFERS_FROM_PARAMS;
  uint rays = 0u;
  for (;;) {
    const uint i = params.first_photon + atomic_inc(&progress[0]);
    if (i >= params.photon_end) break;
    PhotonRecord photon = emit_photon(&scene, &params, casters, caster_count, i);
    for (;;) {
      const Hit hit = trace_closest(SCENE_GEOMETRY_OF(&scene), photon.origin.xyz, photon.dir.xyz, 0.0f, RAY_T_FAR);
      ++rays;
      PhotonRecord child;
      if (!bounce_photon(&scene, &params, photon, hit, candidates, stored, &child)) break;
      photon = child;
    }
  }
  if (rays > 0u) atomic_add(&progress[1], rays);
}
