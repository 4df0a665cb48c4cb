#line 2 "kernels/integrator/shade_surface_path.cl"
/* Stage (path mode): one vertex of every path in the queue.
 *
 * Rules: a path's throughput scales everything it adds. At a hit it adds
 * the emission it sees (weighted by MIS against light sampling unless it
 * arrived by a delta lobe or from the camera); then, if it may scatter again
 * (depth < max_depth: depth counts scattering events, so nbounces is the
 * most scattering events of a path), it samples one light (next-event
 * estimation: an unoccluded contribution, MIS-weighted, in its shadow slot,
 * slot i = path i) and one BSDF direction for its continuation, which
 * survives Russian roulette from rr_depth scattering events on. A miss
 * adds the background. Samples: pixel sequence dimension pairs 2 + 3 depth
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
 * (cone_spread); at a hit the width is cone_width + cone_spread t. A delta lobe keeps the
 * spread, plus the focusing of a curved surface (a sphere of radius R
 * changes it by 2 w / R on reflection, |1 - 1/eta| w / R on refraction,
 * counted as widening: a cone that narrows widens again past its focus); a
 * glossy lobe adds PATH_CONE_GLOSSY_SPREAD alpha, a diffuse one
 * PATH_CONE_DIFFUSE_SPREAD (shared/photon.h). The photon pass's radii are
 * the footprints: a visible point's initial radius, and a later receiver's
 * inline gather radius (at most the pass's cap, caustic_radius). */

#include "lib/photon_grid.h" /* before caustics.h: its gathers need the grid */
#include "lib/camera_sample.h"
#include "lib/caustics.h"
#include "lib/film.h"
#include "lib/material.h"
#include "lib/lights.h"
#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/surface.h"
#include "lib/texture.h"

inline float max3_of(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

/* --check-numerics: what one BSDF sample's weight says (shared/types.h). */
inline void count_bsdf_weight(volatile __global ulong* numerics, uint depth, float3 weight) {
  const float m = fmax(weight.x, fmax(weight.y, weight.z));
  if (!isfinite(m) || !isfinite(weight.x + weight.y + weight.z)) {
    atom_inc(&numerics[NUMERICS_NONFINITE]);
    return;
  }
  const uint d = min(depth, NUMERICS_DEPTHS - 1u);
  atom_inc(&numerics[3u * d]);
  atom_add(&numerics[3u * d + 1u], (ulong)(fmin(fmax(m, 0.0f), 1e6f) * NUMERICS_WEIGHT_SCALE));
  if (m > 1.001f) atom_inc(&numerics[3u * d + 2u]);
}

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

inline uint light_of_hit(__global const uint* light_of_sphere, __global const uint* light_of_cylinder,
                         __global const uint* light_of_triangle, uint prim) {
  const uint type = prim_ref_type(prim), index = prim_ref_index(prim);
  if (type == PRIM_SPHERE) return light_of_sphere[index];
  if (type == PRIM_CYLINDER) return light_of_cylinder[index];
  return light_of_triangle[index];
}

/* Everything a path vertex reads and writes (the kernel's parameters, less
 * the wave's own). */
#if HAS_CAUSTICS
#define PATH_CAUSTIC_PARAMS                                                                   \
  , __global VisiblePoint *restrict visible_points, uint record_visible_points, PHOTON_GRID_PARAMS, \
      float caustic_radius, volatile __global ulong *restrict gather_counters
#define PATH_CAUSTIC_ARGS , visible_points, record_visible_points, PHOTON_GRID_ARGS, caustic_radius, gather_counters
#else
#define PATH_CAUSTIC_PARAMS
#define PATH_CAUSTIC_ARGS
#endif
#if HAS_NUMERIC_CHECKS
#define PATH_NUMERICS_PARAMS , volatile __global ulong *restrict numerics
#define PATH_NUMERICS_ARGS , numerics
#else
#define PATH_NUMERICS_PARAMS
#define PATH_NUMERICS_ARGS
#endif
#if HAS_AUX_PASSES
#define PATH_AUX_PARAMS , uint film_aux_offset
#define PATH_AUX_ARGS , film_aux_offset
#else
#define PATH_AUX_PARAMS
#define PATH_AUX_ARGS
#endif
#define PATH_VERTEX_PARAMS                                                                                  \
  SCENE_SURFACE_PARAMS, __global const Light *restrict lights, __global const uint *restrict light_of_sphere, \
      __global const uint *restrict light_of_cylinder, __global const uint *restrict light_of_triangle,        \
      const PathParams *params, FILM_PARAMS PATH_CAUSTIC_PARAMS PATH_NUMERICS_PARAMS PATH_AUX_PARAMS
#define PATH_VERTEX_ARGS                                                                                   \
  spheres, cylinders, triangles, triangle_shading, materials, textures, texels, environment, lights,        \
      light_of_sphere, light_of_cylinder, light_of_triangle, &params, FILM_ARGS PATH_CAUSTIC_ARGS            \
          PATH_NUMERICS_ARGS PATH_AUX_ARGS

/* One vertex of a path: the ray that arrived and what it hit, in; out, its
 * shadow ray (pixel SHADOW_SLOT_EMPTY: none) and, when the path goes on
 * (true), its continuation. Records by value: the wavefront stage loads
 * and stores them in its queues, the paths shape (trace_paths below) keeps
 * them in registers. *aux_open: the aux passes still wait for this
 * sample's surface (it passed through a mirror or smooth glass here): if
 * the path ends, the caller adds "no surface" for it. */
inline bool shade_path_vertex(PATH_VERTEX_PARAMS, const PathRecord ray, const Hit hit, ShadowRecord* shadow,
                              PathRecord* child_out, bool* aux_open) {
  shadow->pixel = SHADOW_SLOT_EMPTY;
  const float3 throughput = ray.throughput.xyz;
  const float3 d = ray.dir.xyz;
  *aux_open = false;
#if HAS_AUX_PASSES
  /* The first vertex's distance (0 for a miss); the surface below. */
  const bool aux_pending = (ray.flags & PATH_AUX_PENDING) != 0u;
  if (ray.depth == 0u) film_add_aux_depth(FILM_ARGS, film_aux_offset, ray.pixel, hit.prim == PRIM_NONE ? 0.0f : hit.t);
  if (aux_pending && hit.prim == PRIM_NONE) *aux_open = true; /* no surface */
#endif
  if (hit.prim == PRIM_NONE) {
#if HAS_ENVIRONMENT
    if (params->environment_light != LIGHT_NONE) {
      /* The sky, MIS-weighted against its sampling as any light's emission;
       * with the photon pass, light -> caster+ -> receiver is the map's. */
      __global const Light* sky = &lights[params->environment_light];
      float weight = 1.0f;
#if HAS_CAUSTICS
      if (caustic_radius > 0.0f && (ray.flags & PATH_AFTER_RECEIVER) && (ray.flags & PATH_CASTER_SINCE_RECEIVER))
        weight = 0.0f;
#endif
      if (!(ray.flags & PATH_SPECULAR)) {
        if (params->strategy == PATH_STRATEGY_NEE) weight = 0.0f;
        else if (params->strategy == PATH_STRATEGY_MIS)
          weight *= power_heuristic(ray.bsdf_pdf, light_pdf(sky, environment, sky->select_probability,
                                                            ray.origin.xyz, ray.origin.xyz, d));
      }
      if (weight > 0.0f) film_add(FILM_ARGS, ray.pixel, throughput * environment_radiance(environment, d) * weight);
      return false;
    }
#endif
    film_add(FILM_ARGS, ray.pixel, throughput * params->background.xyz);
    return false;
  }
  const SurfacePoint sp = surface_at(spheres, cylinders, triangles, triangle_shading, hit, ray.origin.xyz, d);
  __global const Material* mat = &materials[sp.material];
  const float cone_width = ray.cone_width + ray.cone_spread * hit.t; /* the footprint here */

  /* Emission seen by this path: from the front side (sp.normal is the
   * outward / counter-clockwise normal), or either side of a two-sided one;
   * an emission texture's texel at the hit scales it (a triangle light's
   * emitted.xyz is its material's emission). */
  const bool arrived_by_delta = (ray.flags & PATH_SPECULAR) != 0u;
  bool sees_front = dot(d, sp.normal) < 0.0f || (mat->flags & MATERIAL_TWO_SIDED) != 0u;
  const uint light_index = params->light_count > 0u
                               ? light_of_hit(light_of_sphere, light_of_cylinder, light_of_triangle, hit.prim)
                               : LIGHT_NONE;
#if HAS_CAUSTICS
  /* The photon pass is on for this pass unless `auto` turned it off. */
  const bool photon_map_on = caustic_radius > 0.0f;
  /* light -> caster+ -> receiver: the photon map's, when the photons
   * leave that light (every light in the table emits them; an emissive
   * surface outside it stays the path tracer's, as does the background) */
  if (photon_map_on && light_index != LIGHT_NONE && (ray.flags & PATH_AFTER_RECEIVER) &&
      (ray.flags & PATH_CASTER_SINCE_RECEIVER))
    sees_front = false;
#endif
  if (!sees_front) {
    /* the dark back of an emitter (its reflectance still scatters below) */
  } else if (light_index != LIGHT_NONE) {
    __global const Light* light = &lights[light_index];
    float weight = 1.0f;
    if (!arrived_by_delta) {
      if (params->strategy == PATH_STRATEGY_NEE) weight = 0.0f;
      else if (params->strategy == PATH_STRATEGY_MIS)
        weight = power_heuristic(ray.bsdf_pdf, light_pdf(light, environment, light->select_probability, ray.origin.xyz,
                                                         sp.position, d));
    }
    if (weight > 0.0f)
      film_add(FILM_ARGS, ray.pixel,
               throughput * light->emitted.xyz * material_emission_texel(mat, textures, texels, sp.uv) * weight);
  } else if (max3_of(mat->emission.xyz) > 0.0f) { /* not sampled: BSDF rays find it alone */
    film_add(FILM_ARGS, ray.pixel, throughput * mat->emission.xyz * material_emission_texel(mat, textures, texels, sp.uv));
  }
#if HAS_AUX_PASSES
  if (ray.depth >= params->max_depth && !aux_pending) return false;
#else
  if (ray.depth >= params->max_depth) return false;
#endif

  const Bsdf bsdf = material_bsdf_at(mat, textures, texels, sp.uv);
  const bool opaque = bsdf.kind != BSDF_DIELECTRIC;
  const ShadingFrame frame = shading_frame(bsdf, sp.shading_normal, sp.normal, d);
  const float3 t = frame.t, b = frame.b, n = frame.n, ng = frame.ng;
  const float3 wo = frame_to_local(-d, t, b, n);
#if HAS_AUX_PASSES
  /* The denoiser's albedo and normal: this surface's, unless the path sees
   * through it to the next (perfect mirror, smooth glass), whose albedo
   * then comes with this one's colour in the throughput. */
  if (aux_pending) {
    if (bsdf_passes_aux_through(bsdf))
      *aux_open = true;
    else
      film_add_aux_surface(FILM_ARGS, film_aux_offset, ray.pixel, throughput * bsdf_albedo(bsdf, wo),
                           dot(n, d) > 0.0f ? -n : n);
  }
  if (ray.depth >= params->max_depth) return false;
#endif
#if HAS_CAUSTICS
  const bool caster = photon_map_on && bsdf_casts_caustics(bsdf);
  if (!caster && photon_map_on && record_visible_points && !(ray.flags & PATH_PAST_RECEIVER)) {
    VisiblePoint vp;
    vp.position = pack3(sp.position);
    vp.recorded = 1u;
    vp.normal = pack3(n);
    vp.depth = ray.depth;
    vp.wo = pack3(-d);
    vp.footprint = cone_width;
    vp.beta = pack3(throughput);
    vp.kind = bsdf.kind;
    vp.diffuse = pack3(bsdf.diffuse);
    vp.alpha = bsdf.alpha;
    vp.specular = pack3(bsdf.specular);
    vp.ior = bsdf.ior;
    visible_points[ray.pixel] = vp;
  }
  if (!caster && photon_map_on && (ray.flags & PATH_PAST_RECEIVER) && grid.photon_count > 0u) { /* a later receiver gathers inline */
    const float radius = fmin(cone_width, caustic_radius);
    if (radius > 0.0f)
      film_add(FILM_ARGS, ray.pixel,
               throughput * caustic_radiance(PHOTON_GRID_ARGS, bsdf, t, b, n, wo, sp.position, radius,
                                             (float)params->max_depth - 1.0f - (float)ray.depth,
                                             random_float(hash3(ray.pixel, ray.sample, params->seed),
                                                          0x9a7e0000u + ray.depth),
                                             gather_counters));
  }
  /* Light reaching a caster that leads back to a receiver is the photon map's. */
  const bool nee_is_photon_maps = caster && (ray.flags & PATH_AFTER_RECEIVER);
#endif
  const uint pixel_seed = hash3(ray.pixel, 0u, params->seed);
  const uint pair = 2u + 3u * ray.depth;
  /* The vertex's three 2D samples at once, in the lanes of vectors: each is
   * a long chain of integer multiplies and bit permutations. */
  float2 u_light, u_dir, picks;
  pixel_samples_2d_x3(params->sampler, ray.sample, pair, pixel_seed, &u_light, &u_dir, &picks);

  /* Next-event estimation toward one light. */
  const bool delta_only = bsdf_is_smooth(bsdf) && bsdf.kind != BSDF_PLASTIC;
  bool take_nee = params->light_count > 0u && params->strategy != PATH_STRATEGY_BSDF && !delta_only;
#if HAS_CAUSTICS
  take_nee = take_nee && !nee_is_photon_maps;
#endif
  if (take_nee) {
    const uint li = pick_light(lights, params->light_count, picks.x);
    __global const Light* light = &lights[li];
    LightSample ls;
    if (sample_light(light, environment, light->select_probability, sp.position, u_light, &ls)) {
      ls.radiance *= light_emission_texel(light, triangle_shading, textures, texels, u_light); /* same pdf */
      const float3 wi = frame_to_local(ls.wi, t, b, n);
      const float side = dot(ls.wi, ng);
      if (!opaque || side > 0.0f) {
        const float3 f = bsdf_eval(bsdf, wo, wi);
        if (max3_of(f) > 0.0f) {
          const float weight = ls.delta || params->strategy == PATH_STRATEGY_NEE
                                   ? 1.0f
                                   : power_heuristic(ls.pdf, bsdf_pdf(bsdf, wo, wi));
          const float3 contribution = throughput * f * fabs(wi.z) * ls.radiance * (weight / ls.pdf);
          float3 dir;
          float tmax;
          const float3 origin = spawn_ray_to(sp.position, sp.p_error, sp.normal, ls.point, ls.p_error, ls.normal,
                                                    &dir, &tmax);
          shadow->origin = (float4)(origin, 0.0f);
          shadow->dir = (float4)(dir, 0.0f);
          shadow->contribution = (float4)(contribution, 0.0f);
          shadow->pixel = ray.pixel;
          shadow->tmax = tmax;
        }
      }
    }
  }

  /* The continuation, by BSDF sampling. */
  float3 wi_local, weight;
  float pdf;
  uint flags;
  if (!bsdf_sample(bsdf, wo, (float3)(u_dir, picks.y), &wi_local, &weight, &pdf, &flags)) return false;
#if HAS_NUMERIC_CHECKS
  count_bsdf_weight(numerics, ray.depth, weight);
#endif
  const float3 wi = frame_to_world(wi_local, t, b, n);
  if (opaque && dot(wi, ng) <= 0.0f) return false;
  float3 continued_throughput = throughput * weight;
  if (ray.depth + 1u >= params->rr_depth) {
    const float survive = fmin(0.95f, max3_of(continued_throughput));
    if (!(random_float(hash3(ray.pixel, ray.sample, params->seed), ray.depth) < survive)) return false;
    continued_throughput /= survive;
  }
  if (!(max3_of(continued_throughput) > 0.0f)) return false;
  /* The cone past this vertex (the rules above); only the photon pass reads it. */
  float spread = ray.cone_spread;
#if HAS_CAUSTICS
  if (flags & BSDF_SAMPLED_SPECULAR) {
    if (prim_ref_type(hit.prim) == PRIM_SPHERE) {
      const float inv_r = 1.0f / spheres[prim_ref_index(hit.prim)].center_radius.w;
      spread += cone_width * inv_r *
                ((flags & BSDF_SAMPLED_TRANSMIT) ? fabs(1.0f - 1.0f / dielectric_eta(bsdf, wo)) : 2.0f);
    }
  } else {
    spread += bsdf.kind == BSDF_PLASTIC ? PATH_CONE_DIFFUSE_SPREAD : PATH_CONE_GLOSSY_SPREAD * bsdf.alpha;
  }
#endif
  PathRecord child;
  child.origin = (float4)(spawn_ray_origin(sp.position, sp.p_error, sp.normal, wi), 0.0f);
  child.dir = (float4)(wi, 0.0f);
  child.throughput = (float4)(continued_throughput, 0.0f);
  child.pixel = ray.pixel;
  child.depth = ray.depth + 1u;
  child.sample = ray.sample;
  child.bsdf_pdf = (flags & BSDF_SAMPLED_SPECULAR) ? 0.0f : pdf;
  child.flags = (flags & BSDF_SAMPLED_SPECULAR) ? PATH_SPECULAR : 0u;
  child.cone_width = cone_width;
  child.cone_spread = spread;
#if HAS_AUX_PASSES
  if (*aux_open) child.flags |= PATH_AUX_PENDING;
#endif
#if HAS_CAUSTICS
  const uint caustic_flags = PATH_PAST_RECEIVER | PATH_AFTER_RECEIVER | PATH_CASTER_SINCE_RECEIVER;
  if (!caster) /* leaving a receiver starts a new chain */
    child.flags |= PATH_PAST_RECEIVER | PATH_AFTER_RECEIVER;
  else
    child.flags |= (ray.flags & caustic_flags) | ((ray.flags & PATH_AFTER_RECEIVER) ? PATH_CASTER_SINCE_RECEIVER : 0u);
#endif
  *child_out = child;
  return true;
}

/* The kernel: path i's vertex, then, if the path ended, the wave's next
 * sample in its place (regeneration). With count_pixel_rays (adaptive
 * sampling) each vertex counts its rays for its pixel (pixel_rays: the
 * closest-hit ray that found it, a miss included, and its shadow ray): what
 * a pixel's samples cost, which the allocation weighs. Samples and queue slots are taken
 * per work-group, one global atomic each, not per path: every path of the
 * wave would otherwise contend on the same two counters. No early return,
 * so that every work-item reaches the barriers. */
__kernel void shade_surface_path(SCENE_SURFACE_PARAMS, __global const Light* restrict lights,
                                 __global const uint* restrict light_of_sphere,
                                 __global const uint* restrict light_of_cylinder,
                                 __global const uint* restrict light_of_triangle, PathParams params,
                                 PATH_QUEUE_PARAMS(in), __global const Hit* restrict hits, FILM_PARAMS,
                                 PATH_QUEUE_PARAMS(next), volatile __global uint* restrict cleared_count,
                                 SHADOW_QUEUE_PARAMS(shadow), CameraGPU camera,
                                 volatile __global uint* restrict wave_progress, WAVE_ALLOCATION_PARAMS,
                                 volatile __global ulong* restrict pixel_rays, uint count_pixel_rays PATH_CAUSTIC_PARAMS
                                     PATH_NUMERICS_PARAMS PATH_AUX_PARAMS) {
  __local uint group_starts, group_first_sample, group_pushes, group_first_slot;
  const uint i = get_global_id(0);
  const uint count = *in_count;
  if (i == 0) {
    *cleared_count = 0u; /* the queue iteration j + 1's shade stage pushes into */
    atomic_add(&wave_progress[WAVE_CLOSEST_RAYS], count);
  }
  if (get_local_id(0) == 0) group_starts = group_pushes = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  PathRecord child;
  bool goes_on = false, starts = false;
  if (i < count) {
    bool aux_open;
    ShadowRecord shadow_ray;
    goes_on = shade_path_vertex(PATH_VERTEX_ARGS, path_load(PATH_QUEUE_ARGS(in), i), hits[i], &shadow_ray, &child,
                                &aux_open);
    if (shadow_ray.pixel == SHADOW_SLOT_EMPTY)
      shadow_mark_empty(SHADOW_QUEUE_ARGS(shadow), i);
    else
      shadow_store(SHADOW_QUEUE_ARGS(shadow), i, shadow_ray);
#if HAS_AUX_PASSES
    /* its path ended before a rough surface: none, once */
    if (!goes_on && aux_open)
      film_add_aux_surface(FILM_ARGS, film_aux_offset, in_pixel[i], splat_float3(0.0f), splat_float3(0.0f));
#else
    (void)aux_open;
#endif
    /* its pixel's cost: the ray that found this vertex, and its shadow ray */
    if (count_pixel_rays) atom_add(&pixel_rays[in_pixel[i]], shadow_pixel[i] == SHADOW_SLOT_EMPTY ? 1ul : 2ul);
    starts = !goes_on;
  }
  const uint start_rank = starts ? atomic_inc(&group_starts) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0 && group_starts > 0u)
    group_first_sample = atomic_add(&wave_progress[WAVE_SAMPLES_STARTED], group_starts);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (starts && group_first_sample + start_rank < params.wave_samples) {
    child = camera_sample_path(&camera, &params, group_first_sample + start_rank, WAVE_ALLOCATION_ARGS);
    goes_on = true;
  }
  const uint push_rank = goes_on ? atomic_inc(&group_pushes) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0 && group_pushes > 0u) group_first_slot = atomic_add(next_count, group_pushes);
  barrier(CLK_LOCAL_MEM_FENCE);
  /* A slot past the capacity cannot happen: one record per path at most. */
  if (goes_on && group_first_slot + push_rank < params.ray_capacity)
    path_store(PATH_QUEUE_ARGS(next), group_first_slot + push_rank, child);
}
