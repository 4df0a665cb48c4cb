#line 2 "kernels/photon/bounce_photons.cl"
/* Stage (photon pass): one hit of every photon path in the queue.
 *
 * Rules: at a caster (lib/caustics.h) the photon scatters by the path
 * tracer's own BSDF sampling, its flux carried as photons carry it
 * (photon_weight), while the whole path stays within nbounces scattering
 * events; at a receiver reached after at least one caster it is stored and
 * ends; at a receiver reached straight from the light, or on a miss, it
 * ends unstored (direct light is the path tracer's). Stored photons go to
 * slot = photon index of `candidates` with flag 1 in `stored`, so the
 * compaction that follows keeps them in photon order whatever order the
 * queues ran in: the photon map is the same bits on any device. A stored
 * photon keeps what phong's gather multiplies its flux by (lib/caustics.h):
 * the squared length it travelled from a delta light, 1 / pi from the
 * environment, 1 from a directional light. */

#include "lib/caustics.h"
#include "lib/material.h"
#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/scene_buffers.h"
#include "lib/shading_point.h"
#include "lib/surface.h"
#include "lib/texture.h"

inline float phong_scale(PhotonRecord photon, float length) {
  if (photon.flags & PHOTON_FROM_DISTANT_LIGHT) return 1.0f;
  return (photon.flags & PHOTON_FROM_ENVIRONMENT) ? M_1_PI_F : length * length;
}

/* Photon `photon` at `hit`: stored (candidates and stored, at its index)
 * or scattered; true with its continuation in *child_out. The wavefront
 * stage below and the paths shape (trace_photons.cl) call it. */
inline bool bounce_photon(const SceneBuffers* s, const PhotonPassParams* params, const PhotonRecord photon_in,
                          const Hit hit, __global Photon* restrict candidates, __global uint* restrict stored,
                          PhotonRecord* child_out) {
  if (hit.prim == PRIM_NONE) return false;
  PhotonRecord photon = photon_in;
  const float3 d = photon.dir.xyz;
  const SurfacePoint sp = shading_point_at(SCENE_SURFACE_OF(s), hit, photon.origin.xyz, d);
  __global const Material* mat = &s->materials[sp.material];
  photon.power = make_float4_xyz(photon.power.xyz * material_transmittance_to(mat, &sp, d, hit.t), photon.power.w);
  Bsdf bsdf = material_bsdf_at(mat, s->textures, s->texels, sp.uv, sp.colour,
      material_layer_u(mat, hash3(photon.index, params->pass_index, params->seed), 0x1a7e0000u + photon.depth));
  if (!bsdf_casts_caustics(bsdf)) {
    if (photon.flags & PHOTON_AFTER_CASTER) {
      Photon p;
      p.position = pack3(sp.position);
      p.bounces = (float)photon.depth;
      p.wi = pack3(-d);
      p.phong_scale = phong_scale(photon, photon.path_length + hit.t);
      p.power = photon.power;
      candidates[photon.index] = p;
      stored[photon.index] = 1u;
    }
    return false;
  }
  /* The light path leaves this caster: 1 scattering event here, and at
   * least one more where it is gathered. */
  if (photon.depth + 2u > params->max_depth) return false;
  const bool opaque = bsdf.kind != BSDF_DIELECTRIC;
  const ShadingFrame frame = shading_frame(bsdf, sp.shading_normal, sp.normal, d);
  if (bsdf_has_coat(bsdf)) bsdf.coat_n = material_coat_normal(&sp, &frame);
  const float3 t = frame.t, b = frame.b, n = frame.n, ng = frame.ng;
  const float3 wo = frame_to_local(-d, t, b, n);
  const uint key = hash3(photon.index, params->pass_index, params->seed), dim = 8u + 4u * photon.depth;
  const float3 u = (float3)(random_float(key, dim), random_float(key, dim + 1u), random_float(key, dim + 2u));
  float3 wi_local, weight;
  float pdf;
  uint flags;
  if (!bsdf_sample(bsdf, wo, u, &wi_local, &weight, &pdf, &flags)) return false;
  const float3 wi = frame_to_world(wi_local, t, b, n);
  if (opaque && dot(wi, ng) <= 0.0f) return false;
  const float3 flux = photon.power.xyz * photon_weight(bsdf, wo, weight, flags);
  if (!(fmax(flux.x, fmax(flux.y, flux.z)) > 0.0f)) return false;
  PhotonRecord child = photon;
  child.origin = (float4)(spawn_ray_origin(sp.position, sp.p_error, sp.normal, wi), 0.0f);
  child.dir = (float4)(wi, 0.0f);
  child.power = (float4)(flux, 0.0f);
  child.depth = photon.depth + 1u;
  child.path_length = photon.path_length + hit.t; /* phong's gather, lib/caustics.h */
  child.flags = PHOTON_AFTER_CASTER | (photon.flags & (PHOTON_FROM_ENVIRONMENT | PHOTON_FROM_DISTANT_LIGHT));
  *child_out = child;
  return true;
}

__kernel void bounce_photons(SCENE_BUFFERS_PARAMS, PhotonPassParams params, PHOTON_QUEUE_PARAMS(in),
                             __global const Hit* restrict hits, PHOTON_QUEUE_PARAMS(next), uint ray_capacity,
                             volatile __global uint* restrict cleared_count, volatile __global uint* restrict rays_traced,
                             __global Photon* restrict candidates, __global uint* restrict stored) {
  const uint i = get_global_id(0);
  const uint count = *in_count;
  if (i == 0) { /* the wave loop's counters (host/render/wave_loop.h) */
    *cleared_count = 0u;
    atomic_add(rays_traced, count);
  }
  if (i >= count) return;
  const SceneBuffers scene = SCENE_BUFFERS_FROM_PARAMS;
  PhotonRecord child;
  if (bounce_photon(&scene, &params, photon_load(PHOTON_QUEUE_ARGS(in), i), hits[i], candidates, stored, &child))
    photon_push(PHOTON_QUEUE_ARGS(next), ray_capacity, child);
}
