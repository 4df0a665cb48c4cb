#line 2 "kernels/integrator/shade_path_features.h"
/* What a path vertex does for the features a program may compile in (each
 * nothing without its flag): the denoiser's guides (HAS_AUX_PASSES) and
 * the photon pass (HAS_CAUSTICS). Part of shade_path_vertex.h, whose
 * rules hold here. */
#ifndef CAUSTICA_INTEGRATOR_SHADE_PATH_FEATURES_H
#define CAUSTICA_INTEGRATOR_SHADE_PATH_FEATURES_H

/* Whether the aux passes still wait for this sample's surface. */
inline bool path_aux_pending(const PathRecord* ray) {
#if HAS_AUX_PASSES
  return (ray->flags & PATH_AUX_PENDING) != 0u;
#else
  (void)ray;
  return false;
#endif
}

/* At every vertex, before its surface: the first vertex's distance (0 for
 * a miss); true when a waiting sample missed (it has no surface). */
inline bool path_aux_at_vertex(const PathStageData* d, const PathRecord* ray, const Hit hit) {
#if HAS_AUX_PASSES
  if (ray->depth == 0u)
    film_add_aux_depth(FILM_OF(d), d->film_aux_offset, ray->pixel, hit.prim == PRIM_NONE ? 0.0f : hit.t);
  return path_aux_pending(ray) && hit.prim == PRIM_NONE;
#else
  (void)d;
  (void)ray;
  (void)hit;
  return false;
#endif
}

/* The denoiser's albedo and normal: this surface's, unless the path sees
 * through it to the next (perfect mirror, smooth glass), whose albedo then
 * comes with this one's colour in the throughput; true then (the sample
 * still waits). */
inline bool surface_aux(const PathStageData* d, const PathRecord* ray, const Bsdf* bsdf, const ShadingFrame* frame,
                        float3 wo) {
#if HAS_AUX_PASSES
  if (!path_aux_pending(ray)) return false;
  if (bsdf_passes_aux_through(*bsdf)) return true;
  const float3 n = frame->n;
  film_add_aux_surface(FILM_OF(d), d->film_aux_offset, ray->pixel, ray->throughput.xyz * bsdf_albedo(*bsdf, wo),
                       dot(n, ray->dir.xyz) > 0.0f ? -n : n);
  return false;
#else
  (void)d;
  (void)ray;
  (void)bsdf;
  (void)frame;
  (void)wo;
  return false;
#endif
}

/* The photon pass at a surface: the first receiver records the pixel's
 * visible point (in passes that trace a photon map), a later receiver
 * gathers the latest map inline within its footprint. Returns whether the
 * surface is a caster (the map carries light through it). */
inline bool surface_photon_map(const PathStageData* d, const PathRecord* ray, const SurfacePoint* sp,
                               const Bsdf* bsdf, const ShadingFrame* frame, float3 wo, float cone_width) {
#if HAS_CAUSTICS
  if (!(d->caustic_radius > 0.0f)) return false; /* `auto` turned the pass off */
  if (bsdf_casts_caustics(*bsdf)) return true;
  if (d->record_visible_points && !(ray->flags & PATH_PAST_RECEIVER)) {
    VisiblePoint vp;
    vp.position = pack3(sp->position);
    vp.recorded = 1u;
    vp.normal = pack3(frame->n);
    vp.depth = ray->depth;
    vp.wo = pack3(-ray->dir.xyz);
    vp.footprint = cone_width;
    /* A coat's mirror-like lobe gathers no photons (as plastic's smooth
     * layer does not); the base under it sees 1 - c Fc(wo) of the light. */
    vp.beta = pack3(ray->throughput.xyz * (bsdf_has_coat(*bsdf) ? 1.0f - bsdf_coat_weight(*bsdf, wo) : 1.0f));
    vp.kind = bsdf->kind;
    vp.diffuse = pack3(bsdf->diffuse);
    vp.alpha = bsdf->alpha;
    vp.specular = pack3(bsdf->specular);
    vp.ior = bsdf->ior;
    d->visible_points[ray->pixel] = vp;
  }
  if ((ray->flags & PATH_PAST_RECEIVER) && d->grid.photon_count > 0u) {
    const float radius = fmin(cone_width, d->caustic_radius);
    if (radius > 0.0f)
      film_add(FILM_OF(d), ray->pixel,
               ray->throughput.xyz *
                   caustic_radiance(PHOTON_GRID_OF(d), *bsdf, frame->t, frame->b, frame->n, wo, sp->position, radius,
                                    (float)d->params.max_depth - 1.0f - (float)ray->depth,
                                    random_float(hash3(ray->pixel, ray->sample, d->params.seed), 0x9a7e0000u + ray->depth),
                                    d->gather_counters));
  }
  return false;
#else
  (void)d;
  (void)ray;
  (void)sp;
  (void)bsdf;
  (void)frame;
  (void)wo;
  (void)cone_width;
  return false;
#endif
}

/* The flags a continuation takes from its parent for the features: the
 * aux passes' wait, and where the path is in light -> caster+ -> receiver
 * (leaving a receiver starts a new chain). */
inline uint path_feature_flags_after(const PathRecord* ray, bool aux_open, bool caster) {
  uint flags = 0u;
#if HAS_AUX_PASSES
  if (aux_open) flags |= PATH_AUX_PENDING;
#else
  (void)aux_open;
#endif
#if HAS_CAUSTICS
  const uint chain = PATH_PAST_RECEIVER | PATH_AFTER_RECEIVER | PATH_CASTER_SINCE_RECEIVER;
  if (!caster)
    flags |= PATH_PAST_RECEIVER | PATH_AFTER_RECEIVER;
  else
    flags |= (ray->flags & chain) | ((ray->flags & PATH_AFTER_RECEIVER) ? PATH_CASTER_SINCE_RECEIVER : 0u);
#else
  (void)ray;
  (void)caster;
#endif
  return flags;
}

#endif /* CAUSTICA_INTEGRATOR_SHADE_PATH_FEATURES_H */
