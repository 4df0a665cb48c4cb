#line 2 "kernels/photon/gather_photons.cl"
/* Stage (photon pass): every pixel's visible point gathers this pass's
 * photons and updates the pixel's SPPM statistics (Hachisuka & Jensen
 * 2009), then forgets the visible point.
 *
 * Rules: a pixel's radius starts at its camera path's footprint at its
 * first visible point (the ray cone's width, vp.footprint; --caustic-radius:
 * that radius) and never exceeds the pass's cap, one grid cell: a larger
 * one is reduced to the cap with tau and N scaled by the ratio of the
 * areas (SPPM's own assumption of a density constant within the disk), so
 * radii only ever shrink. Of the photons within r, those whose light path
 * fits in nbounces with the camera path's (bounces + 1 + camera depth <=
 * max_depth) add f(wo, wi) * flux each, in grid order (deterministic),
 * times the camera path's throughput; the query reads at most
 * PHOTON_GATHER_MAX_VISITS photons, weighing each by its stride
 * (lib/caustics.h's gather_photon_flux: unbiased). With M of them (weighted) and N so far:
 *     N' = N + alpha M,   r'^2 = r^2 (N + alpha M) / (N + M),
 *     tau' = (tau + sum) r'^2 / r^2,
 * so both the bias (r -> 0) and the variance (N -> infinity) vanish; the
 * pixel's caustic radiance is tau / (passes pi r^2) (the photons' flux is
 * per pass). A pixel that has found no photon yet shrinks its radius as
 * r^2 (k + alpha) / (k + 1) in pass k (from 1) instead: nothing within the
 * larger radius means nothing within the smaller, so its zero estimate
 * stays valid, and later queries stay cheap. Every pixel also adds this
 * pass's own estimate L = beta sum / (pi r^2) to sum_l, r^2 to sum_r2 and
 * L^2 r^2 to sum_l2 (the error estimate's variance, photon_pass.h), and its radius to the histogram the
 * next pass's cells follow; the visits go to the gather counters
 * (shared/photon.h). */

#include "lib/photon_grid.h" /* before caustics.h: its gathers need the grid */
#include "lib/caustics.h"
#include "lib/rng.h"
#include "lib/sampling.h"

__kernel void gather_photons(PhotonPassParams params, PHOTON_GRID_PARAMS,
                             __global VisiblePoint* restrict visible_points, __global SppmPixel* restrict pixels,
                             volatile __global ulong* restrict gather_counters) {
  /* This process's pixels [first_pixel, pixel_end) (all of them in one process). */
  const uint i = params.first_pixel + get_global_id(0);
  if (i >= params.pixel_end) return;
  SppmPixel px = pixels[i];
  const VisiblePoint vp = visible_points[i];
  visible_points[i].recorded = 0u;
  if (!vp.recorded) {
    if (px.photons == 0.0f && px.radius2 > 0.0f) { /* no point this pass: shrink as below */
      const float k = (float)params.pass_index + 1.0f;
      px.radius2 *= (k + params.alpha) / (k + 1.0f);
      pixels[i] = px;
    }
    return;
  }
  const float cap2 = params.radius_cap * params.radius_cap;
  if (px.radius2 == 0.0f) {
    /* The first visible point sets the radius: the path's footprint there,
     * so the estimate starts blurred by no more than a pixel (through
     * mirrors and glass the cone is an estimate, which is all an initial
     * radius needs). */
    const float footprint = PHOTON_RADIUS_FOOTPRINTS * vp.footprint;
    const float r = params.footprint_radius && footprint > 0.0f ? fmin(params.radius_cap, footprint)
                                                                : params.radius_cap;
    px.radius2 = r * r;
    px.footprint2 = px.radius2;
  } else if (px.radius2 > cap2) {
    const float scale = cap2 / px.radius2;
    px.tau *= scale;
    px.photons *= scale;
    px.radius2 = cap2;
  }
  float3 sum = (float3)(0.0f);
  float found = 0.0f;
  uint visits = 0u;
  if (grid.photon_count > 0u) {
    const Bsdf bsdf = bsdf_of_visible_point(vp);
    const float3 n = unpack3(vp.normal);
    float3 t, b;
    frame_from_normal(n, &t, &b);
    const float3 wo = frame_to_local(unpack3(vp.wo), t, b, n);
    const float bounces_left = (float)params.max_depth - 1.0f - (float)vp.depth;
    sum = gather_photon_flux(PHOTON_GRID_ARGS, bsdf, t, b, n, wo, unpack3(vp.position), sqrt(px.radius2),
                             bounces_left, PHOTON_GATHER_MAX_VISITS,
                             random_float(hash3(i, params.pass_index, params.seed), 0x5eedu), &found, &visits);
  }
  const float3 beta = unpack3(vp.beta);
  const float3 pass_estimate = beta * sum / (M_PI_F * px.radius2);
  px.sum_l += (float4)(pass_estimate, 0.0f);
  px.sum_r2 += px.radius2;
  px.sum_l2 += (float4)(pass_estimate * pass_estimate * px.radius2, 0.0f);
  if (found > 0.0f) {
    const float n_next = px.photons + params.alpha * found;
    const float shrink = n_next / (px.photons + found);
    px.tau = (float4)((px.tau.xyz + beta * sum) * shrink, 0.0f);
    px.photons = n_next;
    px.radius2 *= shrink;
  } else if (px.photons == 0.0f) {
    const float k = (float)params.pass_index + 1.0f;
    px.radius2 *= (k + params.alpha) / (k + 1.0f);
  }
  pixels[i] = px;
  const int radius_bin = (int)floor(2.0f * log2(px.radius2)) + 128; /* 4 log2 r */
  atom_inc(&gather_counters[GATHER_COUNT_RADIUS + (uint)clamp(radius_bin, 0, (int)PHOTON_RADIUS_BINS - 1)]);
  atom_add(&gather_counters[GATHER_COUNT_VISITS_D1], (ulong)visits);
  atom_inc(&gather_counters[GATHER_COUNT_HISTOGRAM_D1 + min(visits / PHOTON_VISIT_BIN_WIDTH, PHOTON_VISIT_BINS - 1u)]);
}
