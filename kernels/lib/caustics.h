#line 2 "kernels/lib/caustics.h"
/* What the photon pass and the path tracer agree on, so that every light
 * path is counted by exactly one of them (issue 13).
 *
 * Casters are conductors and dielectrics smoother than CAUSTIC_CASTER_ALPHA
 * (shared/photon.h); every other surface receives. Photons leave the
 * lights, scatter only at casters, and are stored at the first receiver
 * after at least one caster: they estimate the paths
 *     light -> caster+ -> receiver,
 * gathered at the first receiving vertex of each camera path (D1, seen
 * directly or through casters). The path tracer therefore drops exactly
 * the paths that reach a light from D1 through one or more casters and no
 * receiver: the emission a BSDF-sampled ray finds after D1 -> caster+, and
 * the next-event estimates taken at those casters. Everything else (direct
 * light at D1, light through casters onto later receivers, casters seen
 * from the camera) stays with the path tracer. */
#ifndef CAUSTICA_LIB_CAUSTICS_H
#define CAUSTICA_LIB_CAUSTICS_H

#include "lib/bsdf.h"
#include "shared/photon.h"

inline bool bsdf_casts_caustics(Bsdf b) { return b.kind != BSDF_PLASTIC && b.alpha < CAUSTIC_CASTER_ALPHA; }

/* Path flags (PathRecord.flags) of camera paths past their first receiver. */
#define PATH_PAST_RECEIVER 2u /* D1 is behind: its visible point is recorded */
#define PATH_CHAIN_FROM_D1 4u /* since D1, only casters were passed */
#define PATH_CASTER_AFTER_D1 8u /* ... and at least one of them */

/* Photon path flags (the photon pass reuses PathRecord). */
#define PHOTON_AFTER_CASTER 2u

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
  b.diffuse = v.diffuse.xyz;
  b.specular = v.specular.xyz;
  b.alpha = v.diffuse.w;
  b.ior = v.specular.w;
  b.kind = v.kind;
  return b;
}

#endif /* CAUSTICA_LIB_CAUSTICS_H */
