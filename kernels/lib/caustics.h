#line 2 "kernels/lib/caustics.h"
/* What the photon pass and the path tracer agree on, so that every light
 * path is counted by exactly one of them (issue 13).
 *
 * Casters are conductors and dielectrics smoother than CAUSTIC_CASTER_ALPHA
 * (shared/photon.h); every other surface receives. Photons leave the
 * lights, scatter only at casters, and are stored at the first receiver
 * after at least one caster: they estimate the paths
 *     light -> caster+ -> receiver,
 * gathered at every receiving vertex of each camera path: at the first (D1,
 * seen directly or through casters) by per-pixel SPPM statistics
 * (gather_photons.cl), at later ones (D2, ...: caustics lighting the scene
 * indirectly) inline in shade_surface_path within the pass's shared radius
 * (Knaus & Zwicker 2011, shrinking pass by pass). The path tracer therefore
 * drops exactly the paths that reach a light from a receiver through one or
 * more casters and no other receiver: the emission a BSDF-sampled ray finds
 * after receiver -> caster+, and the next-event estimates taken at those
 * casters. Everything else (direct light at receivers, light from casters
 * seen from the camera before D1) stays with the path tracer. */
#ifndef CAUSTICA_LIB_CAUSTICS_H
#define CAUSTICA_LIB_CAUSTICS_H

#include "lib/bsdf.h"
#include "lib/material.h"
#include "shared/photon.h"

/* The flags this needs are declared with their records (shared/records.h):
 * PATH_PAST_RECEIVER, PATH_AFTER_RECEIVER, PATH_CASTER_SINCE_RECEIVER of
 * camera paths, PHOTON_AFTER_CASTER of photon paths. */

/* The weight bsdf_sample returned, as photons carry it: flux is not
 * rescaled by eta^2 when it crosses into another medium the way radiance is
 * (bsdf.h's rule for camera paths), so transmission undoes that factor. */
inline float3 photon_weight(Bsdf b, float3 wo, float3 weight, uint sampled_flags) {
  if (!(sampled_flags & BSDF_SAMPLED_TRANSMIT)) return weight;
  const float eta = dielectric_eta(b, wo);
  return weight * (eta * eta);
}

inline Bsdf bsdf_of_visible_point(VisiblePoint v) {
  Bsdf b;
  b.diffuse = unpack3(v.diffuse);
  b.specular = unpack3(v.specular);
  b.alpha = v.alpha;
  b.ior = v.ior;
  b.kind = v.kind;
  b.coat = 0.0f; /* the coat's share was taken off beta when the point was recorded */
  b.coat_alpha = 0.0f;
  b.coat_n = make_float3(0.0f, 0.0f, 1.0f);
  return b;
}

/* Phong mode (--caustics on): Whitted shading has no path to leave out, so
 * every diffuse shading point (seen directly or through mirrors and glass)
 * adds the photons' irradiance within a radius shared by the whole pass
 * (Knaus & Zwicker's progressive photon mapping: the radius shrinks pass
 * by pass, the passes are averaged). Phong lights have no distance falloff
 * (its direct term is kd I cos), so a delta light's photon counts in
 * phong's units: its flux times the squared length it travelled, which
 * turns the 1/d^2 of its density back into phong's constant irradiance.
 * The environment's photons (PHOTON_FROM_ENVIRONMENT) carry radiance from
 * infinitely far, with no falloff to undo, and phong shows that radiance
 * as it is at misses: their irradiance E reflects as a Lambertian's
 * kd diffuse E / pi, the path tracer's caustic radiance for the same
 * surface. Phong has no direct light from the sky (only its point lights
 * and the ambient term), so this is light it did not have: the sky
 * focused by casters onto receivers, nothing counted twice. A directional
 * light's photons (PHOTON_FROM_DISTANT_LIGHT) have no falloff either, and
 * phong's direct term for it is kd E cos: their irradiance counts as it
 * is. The factor, d^2, 1 / pi or 1, is stored with the photon
 * (Photon.phong_scale, bounce_photons.cl). */
#ifdef CAUSTICA_LIB_PHOTON_GRID_H
/* Bounded work (issue 19): the sum over this pass's photons within
 * `radius` of p (|x - p|^2 <= radius^2, each photon once, in grid order as
 * lib/photon_grid.h hands them out) of f(wo, wi) * flux, for photons whose
 * light paths fit in the bounces left (photon bounces <= bounces_left),
 * reading at most about max_visits photons: the loops first add up the
 * sizes of the buckets they will visit, and when those exceed max_visits
 * they read only the slots s * j + offset of each bucket (stride s =
 * ceil(total / max_visits), offset uniform in [0, s) from u) and weigh each
 * photon by s. Every photon within the radius is then read with
 * probability exactly 1 / s, so the sum and *found (the photons counted)
 * are unbiased estimates of the full ones, at a cost of at most max_visits
 * photons plus the cells' bucket reads, however many photons a focused
 * caustic piles into them. *visits: the slots read. */
inline float3 gather_photon_flux(PHOTON_GRID_PARAMS, Bsdf bsdf, float3 t, float3 b, float3 n, float3 wo, float3 p,
                                 float radius, float bounces_left, uint max_visits, float u, float* found,
                                 uint* visits) {
  float3 sum = (float3)(0.0f);
  *found = 0.0f;
  *visits = 0u;
  const float radius2 = radius * radius;
  const float reach = radius * 1.00001f; /* as photon_query_begin */
  const int3 lo = photon_grid_cell(grid, p - reach), hi = photon_grid_cell(grid, p + reach);
  /* A radius within one cell spans at most 2 x 2 x 2 cells: their buckets
   * are read once and kept; a larger one (phong's, tests') reads them twice. */
  const int3 span = hi - lo + 1;
  const bool few = span.x <= 2 && span.y <= 2 && span.z <= 2;
  uint starts[8], ends[8];
  uint total = 0u;
  for (int z = lo.z, k = 0; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x, ++k) {
        const uint bucket = photon_grid_bucket(grid, (int3)(x, y, z));
        const uint start = grid_bucket_start[bucket], end = grid_bucket_start[bucket + 1u];
        total += end - start;
        if (few) {
          starts[k] = start;
          ends[k] = end;
        }
      }
  if (total == 0u) return sum;
  const uint stride = total > max_visits ? (total + max_visits - 1u) / max_visits : 1u;
  const uint offset = min((uint)(u * (float)stride), stride - 1u);
  uint read = 0u, counted = 0u;
  for (int z = lo.z, k = 0; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x, ++k) {
        const int3 cell = (int3)(x, y, z);
        uint start, end;
        if (few) {
          start = starts[k];
          end = ends[k];
        } else {
          const uint bucket = photon_grid_bucket(grid, cell);
          start = grid_bucket_start[bucket];
          end = grid_bucket_start[bucket + 1u];
        }
        for (uint slot = start + offset; slot < end; slot += stride) {
          ++read;
          const Photon photon = grid_photons[slot];
          const float3 position = unpack3(photon.position);
          if (photon_distance2(position, p) > radius2) continue;
          /* another cell's photon in a shared bucket: counted with its own cell */
          if (any(photon_grid_cell(grid, position) != cell)) continue;
          if (photon.bounces > bounces_left) continue;
          sum += bsdf_eval(bsdf, wo, frame_to_local(unpack3(photon.wi), t, b, n)) * photon.power.xyz;
          ++counted;
        }
      }
  *visits = read;
  *found = (float)counted * (float)stride;
  return sum * (float)stride;
}

/* Path mode, receivers after D1: the caustic radiance toward wo from this
 * pass's photons within `radius` (gather_photon_flux, at most
 * PHOTON_INLINE_GATHER_MAX_VISITS read); the visits go to the gather
 * counters. */
inline float3 caustic_radiance(PHOTON_GRID_PARAMS, Bsdf bsdf, float3 t, float3 b, float3 n, float3 wo, float3 p,
                               float radius, float bounces_left, float u,
                               volatile __global ulong* gather_counters) {
  float found;
  uint visits;
  const float3 sum = gather_photon_flux(PHOTON_GRID_ARGS, bsdf, t, b, n, wo, p, radius, bounces_left,
                                        PHOTON_INLINE_GATHER_MAX_VISITS, u, &found, &visits);
  atom_add(&gather_counters[GATHER_COUNT_VISITS_LATER], (ulong)visits);
  atom_inc(&gather_counters[GATHER_COUNT_HISTOGRAM_LATER + min(visits / PHOTON_VISIT_BIN_WIDTH, PHOTON_VISIT_BINS - 1u)]);
  return sum / (M_PI_F * radius * radius);
}

inline float3 phong_caustic_irradiance(PHOTON_GRID_PARAMS, float3 p, float3 n, float radius) {
  float3 sum = (float3)(0.0f);
  PhotonQuery query = photon_query_begin(PHOTON_GRID_ARGS, p, radius);
  for (int slot; (slot = photon_query_next(&query, PHOTON_GRID_ARGS)) >= 0;) {
    const Photon photon = grid_photons[slot];
    if (dot(unpack3(photon.wi), n) <= 0.0f) continue; /* arrived on the other side */
    sum += photon.power.xyz * photon.phong_scale;
  }
  return sum / (M_PI_F * radius * radius);
}
#endif

#endif /* CAUSTICA_LIB_CAUSTICS_H */
