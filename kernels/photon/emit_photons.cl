#line 2 "kernels/photon/emit_photons.cl"
/* Stage (photon pass): photon path i of this pass leaves a light.
 *
 * Rules: the light is picked in proportion to its power (the path tracer's
 * table and pick); its type (lib/lights/<type>_light.h) places the photon
 * and, unguided, draws its direction and flux: area lights uniformly by
 * area and by cosine over the emitting side (both sides of a two-sided
 * emitter), flux Le * area * pi * sides; a point light over every
 * direction, I * 4 pi; a spot light within its outer cone. The flux is
 * divided by p_pick and by the pass's photon count so that a pass's photons sum to the
 * lights' power. Random numbers come from the photon's index, the pass and
 * the seed (a counter-based hash), so every photon is the same on any
 * device; its index rides in the record (PhotonRecord.index). A textured
 * emitter's photon carries the texel at its start point (lights.h:
 * light_emission_texel) on top of the flux for emitted.xyz: the point's
 * density is uniform by area still, so the flux is Le(point) |cos| A / pdf.
 *
 * Guided emission (issue 19): only photons that meet a caster before any
 * receiver are ever stored, and on scenes where small glass and metal
 * objects stand on a large ground most photons never do. With caster
 * bounds (a bounding sphere per caster object, host/render/photon_pass.cpp)
 * the direction is drawn instead from the cones those spheres subtend from
 * the emitting point: cone j with probability Omega_j / sum Omega (a point
 * inside a sphere gets the whole sphere of directions, 4 pi), uniformly
 * within it. The density of a direction is then (the number of cones
 * holding it) / sum Omega, and the flux Le |cos| A / (p_pick pdf) (point
 * light: I / (p_pick pdf); spot light: I f / (p_pick pdf)). Every direction that can meet a caster first
 * lies in a cone, so every stored photon path keeps a non-zero density and
 * the photon map's expectation is unchanged; directions that miss every
 * cone would have ended unstored. A direction behind a one-sided emitter
 * carries no flux. The environment's photons have no point to aim from:
 * their direction is drawn from the map and they cross a disk facing it
 * (lib/lights/environment_light.h: environment_emit_through), of the
 * scene's bounding sphere, or, guided, of a sphere around every caster
 * bound (every line that meets a caster crosses it), starting outside the
 * scene either way; they are flagged PHOTON_FROM_ENVIRONMENT (the length
 * they travel from that disk means nothing to phong's gather). A
 * directional light's photons cross the same disks along its one direction
 * (lib/lights/directional_light.h: directional_emit_through), flagged
 * PHOTON_FROM_DISTANT_LIGHT. */

#include "lib/caustics.h"
#include "lib/lights.h"
#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/scene_buffers.h"
#include "lib/surface.h"

/* Light emission sample dimensions of a photon path: 0 pick, 1-2 point,
 * 3-4 direction, 5 side (guided: the caster's cone); bounce k uses 8 + 4k onward (bounce_photons.cl). */
inline float photon_random(uint photon, PhotonPassParams params, uint dimension) {
  return random_float(hash3(photon, params.pass_index, params.seed), dimension);
}

/* The solid angle of caster bound c seen from o, and 1 - cos of its cone's
 * half angle (2: o is inside, every direction). */
inline float caster_solid_angle(float4 c, float3 o, float* one_minus_cos) {
  const float3 d = c.xyz - o;
  const float d2 = dot(d, d), r2 = c.w * c.w;
  *one_minus_cos = d2 <= r2 ? 2.0f : sphere_cone_one_minus_cos(d2, r2);
  return 2.0f * M_PI_F * *one_minus_cos;
}

/* Whether direction w from o is within bound c's cone: the line's
 * distance from the centre, |w x d|, at most the radius, in front of o
 * (the cross product keeps its precision for tiny cones, where a cosine
 * rounds to 1). */
inline bool caster_cone_holds(float4 c, float3 o, float3 w) {
  const float3 d = c.xyz - o;
  if (dot(d, d) <= c.w * c.w) return true;
  const float3 x = cross(w, d);
  return dot(w, d) > 0.0f && dot(x, x) <= c.w * c.w;
}

/* A sphere around every caster bound (not the smallest: the centres'
 * mean, and the farthest bound's reach from it). */
inline float4 enclosing_sphere(__global const float4* restrict casters, uint count) {
  float3 centre = (float3)(0.0f);
  for (uint j = 0u; j < count; ++j) centre += casters[j].xyz;
  centre /= (float)count;
  float radius = 0.0f;
  for (uint j = 0u; j < count; ++j) radius = fmax(radius, length(casters[j].xyz - centre) + casters[j].w);
  return (float4)(centre, radius * 1.0001f);
}

/* The sphere whose disk the photons of a light at infinity cross: the
 * scene's bounding sphere (the light's p0), or, guided, one around every
 * caster bound. */
inline float4 distant_light_disk(__global const Light* l, __global const float4* restrict casters, uint count) {
  return count > 0u ? enclosing_sphere(casters, count) : l->p0;
}

/* A direction from o toward the casters and its density (above). */
inline float3 sample_toward_casters(__global const float4* restrict casters, uint count, float3 o, float pick,
                                    float2 u, float* pdf) {
  float total = 0.0f, omc;
  for (uint j = 0u; j < count; ++j) total += caster_solid_angle(casters[j], o, &omc);
  const float target = pick * total;
  uint chosen = count - 1u;
  float below = 0.0f;
  for (uint j = 0u; j < count; ++j) {
    below += caster_solid_angle(casters[j], o, &omc);
    if (target < below) {
      chosen = j;
      break;
    }
  }
  const float4 c = casters[chosen];
  caster_solid_angle(c, o, &omc);
  const float3 axis = omc >= 2.0f ? (float3)(0.0f, 0.0f, 1.0f) : normalize(c.xyz - o);
  float3 t, b;
  frame_from_normal(axis, &t, &b);
  const float3 w = frame_to_world(sample_uniform_cone(u, omc), t, b, axis);
  uint holding = 0u;
  for (uint j = 0u; j < count; ++j) holding += caster_cone_holds(casters[j], o, w) ? 1u : 0u;
  *pdf = (float)max(holding, 1u) / total; /* its own cone holds it, whatever the rounding says */
  return w;
}

/* Photon i's first ray from its light (the paths shape, trace_photons.cl,
 * calls this too). */
inline PhotonRecord emit_photon(const SceneBuffers* s, const PhotonPassParams* params,
                                __global const float4* restrict casters, uint caster_count, uint i) {
  __global const float* environment = s->environment;
  const uint li = pick_light(s->lights, params->light_count, photon_random(i, *params, 0u));
  __global const Light* l = &s->lights[li];
  const float2 u_point = (float2)(photon_random(i, *params, 1u), photon_random(i, *params, 2u));
  const float2 u_dir = (float2)(photon_random(i, *params, 3u), photon_random(i, *params, 4u));
  float3 p_error, n; /* the point's error bound, as sample_light's (spawn_ray_origin), and its normal */
  const float3 point = light_emission_point(l, environment, u_point, &p_error, &n);
  float3 origin, dir, flux;
  uint flags = 0u;
#if HAS_ENVIRONMENT
  if (l->kind == LIGHT_ENVIRONMENT) {
    flags = PHOTON_FROM_ENVIRONMENT;
    flux = environment_emit_through(environment, l, distant_light_disk(l, casters, caster_count), point, u_dir,
                                    &origin, &dir);
  } else
#endif
  if (l->kind == LIGHT_DIRECTIONAL) {
    flags = PHOTON_FROM_DISTANT_LIGHT;
    flux = directional_emit_through(l, distant_light_disk(l, casters, caster_count), point, &origin, &dir);
  } else if (caster_count > 0u) {
    float pdf;
    dir = sample_toward_casters(casters, caster_count, point, photon_random(i, *params, 5u), u_dir, &pdf);
    flux = light_emitted_toward(l, environment, point, p_error, n, &dir, pdf, &origin);
  } else {
    flux = light_emit(l, environment, point, p_error, n, u_dir, photon_random(i, *params, 5u), &origin, &dir);
  }
  flux *= light_emission_texel(l, s->triangle_shading, s->textures, s->texels, s->triangle_alpha, s->alpha_texels,
                               u_point); /* the texel (and cut-out) at the point */
  PhotonRecord photon;
  photon.origin = (float4)(origin, 0.0f);
  photon.dir = (float4)(dir, 0.0f);
  photon.power = (float4)(flux / (l->select_probability * (float)params->photon_count), 0.0f);
  photon.index = i;
  photon.depth = 0u;
  photon.path_length = 0.0f;
  photon.flags = flags;
  return photon;
}

__kernel void emit_photons(SCENE_BUFFERS_PARAMS, PhotonPassParams params,
                           __global const float4* restrict casters, uint caster_count, PHOTON_QUEUE_PARAMS(out),
                           __global uint* restrict next_count) {
  /* This process's photons [first_photon, photon_end) (all of them in one
   * process): photon i's random numbers are keyed by i, so a share traces
   * exactly the photons one process would, in queue slots from 0. */
  const uint slot = get_global_id(0), i = params.first_photon + slot;
  if (slot == 0) { /* the wave loop's counts (host/render/wave_loop.h): the host writes none */
    *out_count = params.photon_end - params.first_photon;
    *next_count = 0u;
  }
  if (i >= params.photon_end) return;
  const SceneBuffers scene = SCENE_BUFFERS_FROM_PARAMS;
  photon_store(PHOTON_QUEUE_ARGS(out), slot, emit_photon(&scene, &params, casters, caster_count, i));
}
