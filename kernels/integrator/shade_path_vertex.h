#line 2 "kernels/integrator/shade_path_vertex.h"
/* One vertex of a path, split by purpose as Cycles' shade_surface is:
 * path_miss (the background), surface_emission (what the path sees),
 * surface_direct_light (next-event estimation: pick, sample, shadow ray),
 * surface_bounce (BSDF sample, roulette, the continuation), and what the
 * denoiser's guides and the photon pass take at a surface. shade_path_vertex
 * calls them in order; both shapes call it (the wavefront's
 * shade_surface_path.cl over a queue, the CPU's trace_paths.cl in a loop).
 *
 * Rules: a path's throughput scales everything it adds. At a hit it adds
 * the emission it sees (weighted by MIS against light sampling unless it
 * arrived by a delta lobe or from the camera); then, if it may scatter again
 * (depth < max_depth: depth counts scattering events, so nbounces is the
 * most scattering events of a path), it samples one light (an unoccluded
 * contribution, MIS-weighted, as its shadow ray) and one BSDF direction for
 * its continuation, which survives Russian roulette from rr_depth
 * scattering events on. Samples: pixel sequence dimension pairs 2 + 3 depth
 * (light position), 3 + 3 depth (BSDF direction), 4 + 3 depth (light pick,
 * lobe pick); roulette uses an independent hash. Opaque surfaces are
 * two-sided (the frame turns toward the path); dielectrics keep the outward
 * normal so that the side tells inside from outside. No direction below the
 * geometric surface of an opaque material is followed (no light leaks
 * through shading normals). With the photon pass (HAS_CAUSTICS), the
 * first receiving vertex records the pixel's visible point (in passes that
 * trace a photon map: record_visible_points), later ones gather the latest
 * photon map inline, and the paths the photon map covers are dropped here
 * (lib/caustics.h).
 *
 * Ray cones (Amanatides 1984; Akenine-Moller et al. 2019): a path carries
 * its footprint's width at its origin (cone_width) and its spread angle
 * (cone_spread); at a hit the width is cone_width + cone_spread t. A delta
 * lobe keeps the spread, plus the focusing of a curved surface (a sphere of
 * radius R changes it by 2 w / R on reflection, |1 - 1/eta| w / R on
 * refraction, counted as widening: a cone that narrows widens again past
 * its focus); a glossy lobe adds PATH_CONE_GLOSSY_SPREAD alpha, a diffuse
 * one PATH_CONE_DIFFUSE_SPREAD (shared/photon.h). The photon pass's radii
 * are the footprints: a visible point's initial radius, and a later
 * receiver's inline gather radius (at most the pass's cap, caustic_radius). */
#ifndef CAUSTICA_INTEGRATOR_SHADE_PATH_VERTEX_H
#define CAUSTICA_INTEGRATOR_SHADE_PATH_VERTEX_H

#include "integrator/path_stage_data.h"
#include "lib/caustics.h"
#include "lib/light_pick.h"
#include "lib/lights.h"
#include "lib/material.h"
#include "lib/rng.h"
#include "lib/shading_point.h"
#include "lib/texture.h"

inline float max3_of(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

inline float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  if (a2 + b2 < INFINITY) return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
  /* A density beyond sqrt(FLT_MAX) (a light seen edge-on from its own
   * plane): the ratio form, which inf / inf would make NaN. */
  if (!(a > 0.0f)) return 0.0f;
  if (isinf(a)) return isinf(b) ? 0.5f : 1.0f;
  const float r = b / a;
  return 1.0f / (1.0f + r * r);
}

/* The weight of the emission of `light` a path found at its point q,
 * against sampling that light (light_pdf); 1 after a delta lobe. */
inline float emission_mis_weight(const PathStageData* d, const PathRecord* ray, uint light_index, float3 q) {
  if (ray->flags & PATH_SPECULAR) return 1.0f;
  if (d->params.strategy == PATH_STRATEGY_NEE) return 0.0f;
  if (d->params.strategy != PATH_STRATEGY_MIS) return 1.0f;
  __global const Light* light = &d->scene.lights[light_index];
  const float pick = light_pick_probability(&d->scene, light_index, ray->origin.xyz, ray->light_normal);
  return power_heuristic(ray->bsdf_pdf, light_pdf(light, d->scene.environment, pick, ray->origin.xyz, q, ray->dir.xyz));
}

/* Light -> caster+ -> receiver: the photon map's when the pass has one. */
inline bool path_is_photon_maps(const PathStageData* d, const PathRecord* ray) {
#if HAS_CAUSTICS
  return d->caustic_radius > 0.0f && (ray->flags & PATH_AFTER_RECEIVER) && (ray->flags & PATH_CASTER_SINCE_RECEIVER);
#else
  (void)d;
  (void)ray;
  return false;
#endif
}

/* A path that left the scene: the sky, MIS-weighted against its sampling
 * as any light's emission, or the background colour. */
inline void path_miss(const PathStageData* d, const PathRecord* ray) {
  const float3 dir = ray->dir.xyz;
#if HAS_ENVIRONMENT
  if (d->params.environment_light != LIGHT_NONE) {
    if (path_is_photon_maps(d, ray)) return;
    const float weight = emission_mis_weight(d, ray, d->params.environment_light, ray->origin.xyz);
    if (weight > 0.0f)
      film_add(FILM_OF(d), ray->pixel, ray->throughput.xyz * environment_radiance(d->scene.environment, dir) * weight);
    return;
  }
#endif
  film_add(FILM_OF(d), ray->pixel, ray->throughput.xyz * d->params.background.xyz);
}

/* The emission the path sees at its hit: from the front side (sp.normal is
 * the outward / counter-clockwise normal), or either side of a two-sided
 * one; an emission texture's texel at the hit scales it (a triangle
 * light's emitted.xyz is its material's emission). A light of the table
 * is MIS-weighted against its sampling; an emissive surface outside it is
 * found by BSDF rays alone. */
inline void surface_emission(const PathStageData* d, const PathRecord* ray, uint prim, const SurfacePoint* sp,
                             __global const Material* mat) {
  const float3 dir = ray->dir.xyz;
  if (!(dot(dir, sp->normal) < 0.0f || (mat->flags & MATERIAL_TWO_SIDED) != 0u)) return; /* its dark back */
  const uint light_index = d->params.light_count > 0u ? light_of_primitive(&d->scene, prim) : LIGHT_NONE;
  if (light_index != LIGHT_NONE) {
    /* every light in the table emits photons: its caustics are the map's */
    if (path_is_photon_maps(d, ray)) return;
    __global const Light* light = &d->scene.lights[light_index];
    const float weight = emission_mis_weight(d, ray, light_index, sp->position);
    if (weight > 0.0f)
      film_add(FILM_OF(d), ray->pixel,
               ray->throughput.xyz * light->emitted.xyz *
                   material_emission_texel(mat, d->scene.textures, d->scene.texels, sp->uv) * weight);
  } else if (max3_of(mat->emission.xyz) > 0.0f) {
    film_add(FILM_OF(d), ray->pixel,
             ray->throughput.xyz * mat->emission.xyz *
                 material_emission_texel(mat, d->scene.textures, d->scene.texels, sp->uv));
  }
}

/* Next-event estimation toward one light (picked by power, or by the light
 * tree from this point: lib/light_pick.h): its unoccluded
 * contribution as a shadow ray (pixel SHADOW_SLOT_EMPTY: none). */
inline void surface_direct_light(const PathStageData* d, const PathRecord* ray, const SurfacePoint* sp,
                                 const Bsdf* bsdf, const ShadingFrame* frame, uint light_normal, float3 wo,
                                 float2 u_light, float u_pick, ShadowRecord* shadow) {
  const SceneBuffers* s = &d->scene;
  float pick;
  const uint li = pick_light_at(s, d->params.light_count, sp->position, light_normal, u_pick, &pick);
  __global const Light* light = &s->lights[li];
  LightSample ls;
  if (!sample_light(light, s->environment, pick, sp->position, u_light, &ls)) return;
  ls.radiance *= light_emission_texel(light, s->triangle_shading, s->textures, s->texels, s->triangle_alpha,
                                      s->alpha_texels, u_light); /* same pdf */
  const float3 wi = frame_to_local(ls.wi, frame->t, frame->b, frame->n);
  if (bsdf->kind != BSDF_DIELECTRIC && !(dot(ls.wi, frame->ng) > 0.0f)) return; /* below an opaque surface */
  const float3 f = bsdf_eval(*bsdf, wo, wi);
  if (!(max3_of(f) > 0.0f)) return;
  const float weight =
      ls.delta || d->params.strategy == PATH_STRATEGY_NEE ? 1.0f : power_heuristic(ls.pdf, bsdf_pdf(*bsdf, wo, wi));
  float3 dir;
  float tmax;
  const float3 origin =
      spawn_ray_to(sp->position, sp->p_error, sp->normal, ls.point, ls.p_error, ls.normal, &dir, &tmax);
  shadow->origin = (float4)(origin, 0.0f);
  shadow->dir = (float4)(dir, 0.0f);
  shadow->contribution = (float4)(ray->throughput.xyz * f * fabs(wi.z) * ls.radiance * (weight / ls.pdf), 0.0f);
  shadow->pixel = ray->pixel;
  shadow->tmax = tmax;
}

/* --check-numerics: what one BSDF sample's weight says (shared/types.h). */
inline void count_bsdf_weight(volatile __global ulong* numerics, uint depth, float3 weight) {
  const float m = fmax(weight.x, fmax(weight.y, weight.z));
  if (!isfinite(m) || !isfinite(weight.x + weight.y + weight.z)) {
    atom_inc(&numerics[NUMERICS_NONFINITE]);
    return;
  }
  const uint dd = min(depth, NUMERICS_DEPTHS - 1u);
  atom_inc(&numerics[3u * dd]);
  atom_add(&numerics[3u * dd + 1u], (ulong)(fmin(fmax(m, 0.0f), 1e6f) * NUMERICS_WEIGHT_SCALE));
  if (m > 1.001f) atom_inc(&numerics[3u * dd + 2u]);
}

/* The continuation: a BSDF sample, Russian roulette, the cone past this
 * vertex (only the photon pass reads it); true with *child when the path
 * goes on. */
inline bool surface_bounce(const PathStageData* d, const PathRecord* ray, uint prim, const SurfacePoint* sp,
                           const Bsdf* bsdf, const ShadingFrame* frame, uint light_normal, float3 wo, float3 u_bsdf,
                           float cone_width, PathRecord* child) {
  float3 wi_local, weight;
  float pdf;
  uint flags;
  if (!bsdf_sample(*bsdf, wo, u_bsdf, &wi_local, &weight, &pdf, &flags)) return false;
#if HAS_NUMERIC_CHECKS
  count_bsdf_weight(d->numerics, ray->depth, weight);
#endif
  const float3 wi = frame_to_world(wi_local, frame->t, frame->b, frame->n);
  if (bsdf->kind != BSDF_DIELECTRIC && dot(wi, frame->ng) <= 0.0f) return false;
  float3 throughput = ray->throughput.xyz * weight;
  if (ray->depth + 1u >= d->params.rr_depth) {
    const float survive = fmin(0.95f, max3_of(throughput));
    if (!(random_float(hash3(ray->pixel, ray->sample, d->params.seed), ray->depth) < survive)) return false;
    throughput /= survive;
  }
  if (!(max3_of(throughput) > 0.0f)) return false;
  float spread = ray->cone_spread;
#if HAS_CAUSTICS
  if (flags & BSDF_SAMPLED_SPECULAR) {
    if (prim_ref_type(prim) == PRIM_SPHERE) {
      const float inv_r = 1.0f / d->scene.spheres[prim_ref_index(prim)].center_radius.w;
      spread += cone_width * inv_r *
                ((flags & BSDF_SAMPLED_TRANSMIT) ? fabs(1.0f - 1.0f / dielectric_eta(*bsdf, wo)) : 2.0f);
    }
  } else {
    spread += bsdf->kind == BSDF_PLASTIC ? PATH_CONE_DIFFUSE_SPREAD : PATH_CONE_GLOSSY_SPREAD * bsdf->alpha;
  }
#else
  (void)prim;
#endif
  child->origin = (float4)(spawn_ray_origin(sp->position, sp->p_error, sp->normal, wi), 0.0f);
  child->dir = (float4)(wi, 0.0f);
  child->throughput = (float4)(throughput, 0.0f);
  child->pixel = ray->pixel;
  child->depth = ray->depth + 1u;
  child->sample = ray->sample;
  child->bsdf_pdf = (flags & BSDF_SAMPLED_SPECULAR) ? 0.0f : pdf;
  child->flags = (flags & BSDF_SAMPLED_SPECULAR) ? PATH_SPECULAR : 0u;
  child->cone_width = cone_width;
  child->cone_spread = spread;
  child->light_normal = light_normal; /* what MIS asks the light tree with where this ray ends */
  return true;
}

#include "integrator/shade_path_features.h"

/* One vertex: the ray that arrived and what it hit, in; out, its shadow ray
 * (pixel SHADOW_SLOT_EMPTY: none) and, when the path goes on (true), its
 * continuation. Records by value: the wavefront stage loads and stores
 * them in its queues, the paths shape keeps them in registers. *aux_open:
 * the aux passes still wait for this sample's surface (it passed through a
 * mirror or smooth glass here): if the path ends, the caller adds "no
 * surface" for it. */
inline bool shade_path_vertex(const PathStageData* d, const PathRecord ray_in, const Hit hit, ShadowRecord* shadow,
                              PathRecord* child, bool* aux_open) {
  PathRecord ray = ray_in;
  shadow->pixel = SHADOW_SLOT_EMPTY;
  *aux_open = path_aux_at_vertex(d, &ray, hit);
  if (hit.prim == PRIM_NONE) {
    path_miss(d, &ray);
    return false;
  }
  const SceneBuffers* s = &d->scene;
  const SurfacePoint sp = shading_point_at(SCENE_SURFACE_OF(s), hit, ray.origin.xyz, ray.dir.xyz);
  __global const Material* mat = &s->materials[sp.material];
  ray.throughput = make_float4_xyz(ray.throughput.xyz * material_transmittance_to(mat, &sp, ray.dir.xyz, hit.t),
                                   ray.throughput.w);
  surface_emission(d, &ray, hit.prim, &sp, mat);
  if (ray.depth >= d->params.max_depth && !path_aux_pending(&ray)) return false;

  Bsdf bsdf = material_bsdf_at(
      mat, s->textures, s->texels, sp.uv, sp.colour,
      material_layer_u(mat, hash3(ray.pixel, ray.sample, d->params.seed), 0x1a7e0000u + ray.depth));
  const ShadingFrame frame = shading_frame(bsdf, sp.shading_normal, sp.normal, ray.dir.xyz);
  if (bsdf_has_coat(bsdf)) bsdf.coat_n = material_coat_normal(&sp, &frame);
  const float3 wo = frame_to_local(-ray.dir.xyz, frame.t, frame.b, frame.n);
  *aux_open = surface_aux(d, &ray, &bsdf, &frame, wo);
  if (ray.depth >= d->params.max_depth) return false;
  const float cone_width = ray.cone_width + ray.cone_spread * hit.t; /* the footprint here */
  const bool caster = surface_photon_map(d, &ray, &sp, &bsdf, &frame, wo, cone_width);

  /* The vertex's three 2D samples at once, in the lanes of vectors: each is
   * a long chain of integer multiplies and bit permutations. */
  float2 u_light, u_dir, picks;
  pixel_samples_2d_x3(d->params.sampler, ray.sample, 2u + 3u * ray.depth, hash3(ray.pixel, 0u, d->params.seed),
                      &u_light, &u_dir, &picks);
  /* Light reaching a caster that leads back to a receiver is the photon map's. */
  const bool nee_is_photon_maps = caster && (ray.flags & PATH_AFTER_RECEIVER);
  const bool delta_only = bsdf_is_delta_only(bsdf);
  const uint light_normal = light_tree_normal_at(&bsdf, &frame);
  if (d->params.light_count > 0u && d->params.strategy != PATH_STRATEGY_BSDF && !delta_only && !nee_is_photon_maps)
    surface_direct_light(d, &ray, &sp, &bsdf, &frame, light_normal, wo, u_light, picks.x, shadow);

  if (!surface_bounce(d, &ray, hit.prim, &sp, &bsdf, &frame, light_normal, wo, (float3)(u_dir, picks.y), cone_width,
                      child))
    return false;
  child->flags |= path_feature_flags_after(&ray, *aux_open, caster);
  return true;
}

#endif /* CAUSTICA_INTEGRATOR_SHADE_PATH_VERTEX_H */
