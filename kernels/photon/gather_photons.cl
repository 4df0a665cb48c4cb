#line 2 "kernels/photon/gather_photons.cl"
/* Stage (photon pass): every pixel's visible point gathers this pass's
 * photons and updates the pixel's SPPM statistics (Hachisuka & Jensen
 * 2009), then forgets the visible point.
 *
 * Rules: of the photons within the pixel's radius r, those whose light path
 * fits in nbounces with the camera path's (bounces + 1 + camera depth <=
 * max_depth) add f(wo, wi) * flux each, in grid order (deterministic), times
 * the camera path's throughput. With M of them and N so far:
 *     N' = N + alpha M,   r'^2 = r^2 (N + alpha M) / (N + M),
 *     tau' = (tau + sum) r'^2 / r^2,
 * so both the bias (r -> 0) and the variance (N -> infinity) vanish; the
 * pixel's caustic radiance is tau / (passes pi r^2) (the photons' flux is
 * per pass). A pixel that has found no photon yet shrinks its radius as
 * r^2 (k + alpha) / (k + 1) in pass k (from 1) instead: nothing within the larger
 * radius means nothing within the smaller, so its zero estimate stays
 * valid, and later queries stay cheap. The largest radius^2 is kept (as
 * float bits, which order like uints for positive floats) to size the next
 * pass's grid. */

#include "lib/caustics.h"
#include "lib/photon_grid.h"
#include "lib/sampling.h"

__kernel void gather_photons(PhotonPassParams params, PHOTON_GRID_PARAMS,
                             __global VisiblePoint* restrict visible_points, __global SppmPixel* restrict pixels,
                             volatile __global uint* restrict largest_radius2_bits) {
  const uint i = get_global_id(0);
  if (i >= params.pixel_count) return;
  SppmPixel px = pixels[i];
  const VisiblePoint vp = visible_points[i];
  if (vp.position.w > 0.0f && px.radius2 == 0.0f) {
    /* The first visible point sets the radius: a pixel's footprint there,
     * so the estimate starts blurred by no more than a pixel, at most the
     * cap (the footprint is the camera's; through mirrors and glass it is
     * only an estimate, which is all an initial radius needs). */
    const float footprint = PHOTON_RADIUS_FOOTPRINTS * params.camera.w * length(vp.position.xyz - params.camera.xyz);
    const float r = params.camera.w > 0.0f ? fmin(params.radius_cap, footprint) : params.radius_cap;
    px.radius2 = r * r;
  }
  float3 sum = (float3)(0.0f);
  float found = 0.0f;
  if (vp.position.w > 0.0f && grid.photon_count > 0u && px.radius2 > 0.0f) {
    visible_points[i].position.w = 0.0f;
    const Bsdf bsdf = bsdf_of_visible_point(vp);
    const float3 n = vp.normal.xyz;
    float3 t, b;
    frame_from_normal(n, &t, &b);
    const float3 wo = frame_to_local(vp.wo.xyz, t, b, n);
    const float bounces_left = (float)params.max_depth - 1.0f - vp.normal.w;
    PhotonQuery query = photon_query_begin(PHOTON_GRID_ARGS, vp.position.xyz, sqrt(px.radius2));
    for (int slot; (slot = photon_query_next(&query, PHOTON_GRID_ARGS)) >= 0;) {
      const Photon photon = grid_photons[slot];
      if (photon.position.w > bounces_left) continue;
      sum += bsdf_eval(bsdf, wo, frame_to_local(photon.wi.xyz, t, b, n)) * photon.power.xyz;
      found += 1.0f;
    }
  } else {
    visible_points[i].position.w = 0.0f;
  }
  if (found > 0.0f) {
    const float n_next = px.photons + params.alpha * found;
    const float shrink = n_next / (px.photons + found);
    px.tau = (float4)((px.tau.xyz + vp.beta.xyz * sum) * shrink, 0.0f);
    px.photons = n_next;
    px.radius2 *= shrink;
  } else if (px.photons == 0.0f && px.radius2 > 0.0f) {
    const float k = (float)params.pass_index + 1.0f;
    px.radius2 *= (k + params.alpha) / (k + 1.0f);
  }
  pixels[i] = px;
  atomic_max(largest_radius2_bits, as_uint(px.radius2));
}
