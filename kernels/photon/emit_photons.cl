#line 2 "kernels/photon/emit_photons.cl"
/* Stage (photon pass): photon path i of this pass leaves a light.
 *
 * Rules: the light is picked in proportion to its power (the path tracer's
 * table and pick), the point uniformly by area and the direction by cosine
 * over the emitting side (both sides of a two-sided emitter; every
 * direction of a point light). The photon's flux is then
 *     Le * area * pi * sides / p_pick   (point light: I * 4 pi / p_pick),
 * divided by the pass's photon count so that a pass's photons sum to the
 * lights' power. Random numbers come from the photon's index, the pass and
 * the seed (a counter-based hash), so every photon is the same on any
 * device; its index rides in the record's pixel field. */

#include "lib/caustics.h"
#include "lib/path_lights.h"
#include "lib/queue.h"
#include "lib/rng.h"
#include "lib/surface.h"

/* Light emission sample dimensions of a photon path: 0 pick, 1-2 point,
 * 3-4 direction, 5 side; bounce k uses 8 + 4k onward (bounce_photons.cl). */
inline float photon_random(uint photon, PhotonPassParams params, uint dimension) {
  return random_float(hash3(photon, params.pass_index, params.seed), dimension);
}

__kernel void emit_photons(__global const PathLight* restrict lights, PhotonPassParams params,
                           PATH_QUEUE_PARAMS(out)) {
  const uint i = get_global_id(0);
  if (i >= params.photon_count) return;
  const uint li = pick_light(lights, params.light_count, photon_random(i, params, 0u));
  __global const PathLight* l = &lights[li];
  const float2 u_point = (float2)(photon_random(i, params, 1u), photon_random(i, params, 2u));
  const float2 u_dir = (float2)(photon_random(i, params, 3u), photon_random(i, params, 4u));
  float3 origin, dir, flux;
  if (l->kind == LIGHT_POINT) {
    origin = l->p0.xyz;
    dir = sample_uniform_sphere(u_dir);
    flux = l->emitted.xyz * (4.0f * M_PI_F);
  } else {
    float3 n, p_error; /* the point's error bound, as sample_light's (spawn_ray_origin) */
    origin = sample_light_surface(l, u_point, &p_error, &n);
    float sides = 1.0f;
    if (l->flags & LIGHT_TWO_SIDED) {
      sides = 2.0f;
      if (photon_random(i, params, 5u) < 0.5f) n = -n;
    }
    float3 t, b;
    frame_from_normal(n, &t, &b);
    dir = frame_to_world(sample_cosine_hemisphere(u_dir), t, b, n);
    origin = spawn_ray_origin(origin, p_error, n, dir); /* off the light's own surface */
    flux = l->emitted.xyz * (l->emitted.w * M_PI_F * sides);
  }
  PathRecord photon;
  photon.origin = (float4)(origin, 0.0f);
  photon.dir = (float4)(dir, 0.0f);
  photon.throughput = (float4)(flux / (l->select_probability * (float)params.photon_count), 0.0f);
  photon.pixel = i;
  photon.depth = 0u;
  photon.bsdf_pdf = 0.0f;
  photon.flags = 0u;
  path_store(PATH_QUEUE_ARGS(out), i, photon);
}
