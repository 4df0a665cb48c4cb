#line 2 "kernels/lib/lights/light_common.h"
/* What every light type's file (kernels/lib/lights/<type>_light.h) shares: the
 * sample it returns and the area-light helpers.
 *
 * Rules: a light type's file defines six functions, named
 * <type>_light_<what> (the registry, lib/lights.h, dispatches on
 * Light.kind):
 *   sample(l, p, u, s)            next-event estimation from p; s->pdf per unit
 *                                 solid angle WITHOUT the pick probability (1 for a delta light)
 *   pdf(l, p, q, wi)              that density for a BSDF-sampled ray from p that
 *                                 reached point q of the light (0 for delta lights)
 *   intensity_toward(l, w)        a delta light's intensity along w (phong's shading)
 *   emission_point(l, u, e, n)    a photon's start, its error bound and the surface normal (0: a point)
 *   emit(l, point, e, n, u, side, origin, dir)
 *                                 an unguided photon direction; returns its flux before the pick
 *                                 probability and the pass's photon count
 *   emitted_toward(l, point, e, n, dir, pdf, origin)
 *                                 the flux of a photon sent along *dir with density pdf (guided
 *                                 emission, emit_photons.cl); may zero *dir when no flux leaves
 * Area types write four of them with AREA_LIGHT_SAMPLE_BY_AREA and
 * AREA_LIGHT_EMISSION (below). Every type takes the same parameters, used
 * or not ((void) marks the unused ones on the host, where they would warn).
 * Radiance conventions (scenes/FORMAT.md): a point light's intensity I gives
 * radiance I / d^2; area lights emit their radiance `emitted` from their
 * front side, both sides with LIGHT_TWO_SIDED. */
#ifndef CAUSTICA_LIB_LIGHTS_LIGHT_COMMON_H
#define CAUSTICA_LIB_LIGHTS_LIGHT_COMMON_H

#include "lib/geometry.h"
#include "lib/sampling.h"
#include "shared/types.h"

typedef struct {
  float3 wi;       /* unit direction toward the light */
  float distance;  /* to the sampled point */
  float3 point;    /* the sampled point: the shadow ray aims at it (spawn_ray_to, geometry.h) */
  float3 p_error;  /* bound on the sampled point's error per component (shadow_ray_tmax, geometry.h) */
  float3 normal;   /* the light's surface normal at the point, either side; zero for a point light */
  float3 radiance; /* arriving along -wi, before visibility */
  float pdf;       /* solid angle x pick probability; the pick probability alone for a delta light */
  bool delta;
} LightSample;

/* Solid-angle density (without the pick probability) of reaching point q
 * with normal n_l on an area light of the given area from p. */
inline float area_to_solid_angle(float3 p, float3 q, float3 wi, float area, float3 n_l) {
  const float cos_l = fabs(dot(wi, n_l));
  if (!(cos_l > 0.0f) || !(area > 0.0f)) return 0.0f;
  const float3 d = q - p;
  return dot(d, d) / (cos_l * area);
}

/* Does the light's surface at q, with emitting-side normal n_l, shine
 * toward the point that wi (from that point toward q) comes from? */
inline bool light_faces(__global const Light* l, float3 wi, float3 n_l) {
  return (l->flags & LIGHT_TWO_SIDED) != 0u || dot(wi, n_l) < 0.0f;
}

/* A sample toward point q of an area light (normal n_l, error bound
 * p_error): all but its density; false when q does not shine toward p. */
inline bool aim_at_light_point(__global const Light* l, float3 p, float3 q, float3 p_error, float3 n_l,
                               LightSample* s) {
  s->p_error = p_error;
  const float3 d = q - p;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return false;
  s->distance = sqrt(d2);
  s->wi = d / s->distance;
  s->point = q;
  if (!light_faces(l, s->wi, n_l)) return false;
  s->normal = n_l;
  s->radiance = l->emitted.xyz;
  return true;
}

/* Next-event estimation toward point q drawn uniformly by area on an area
 * light. */
inline bool sample_area_light_point(__global const Light* l, float3 p, float3 q, float3 p_error, float3 n_l,
                                    LightSample* s) {
  if (!aim_at_light_point(l, p, q, p_error, n_l, s)) return false;
  s->pdf = area_to_solid_angle(p, q, s->wi, l->emitted.w, n_l);
  /* An infinite density (the light edge-on, cos_l near 0) carries nothing. */
  return s->pdf > 0.0f && s->pdf < INFINITY;
}

/* Next-event estimation toward point q of a planar light drawn with the
 * given solid-angle density (lib/spherical_sampling.h). */
inline bool sample_planar_light_point(__global const Light* l, float3 p, float3 q, float3 p_error, float3 n_l,
                                      float pdf, LightSample* s) {
  if (!aim_at_light_point(l, p, q, p_error, n_l, s)) return false;
  s->pdf = pdf;
  return s->pdf > 0.0f && s->pdf < INFINITY;
}

/* A delta light at l->p0 seen from p: direction, distance, the point. */
inline bool sample_delta_light_position(__global const Light* l, float3 p, LightSample* s, float* d2_out) {
  const float3 d = l->p0.xyz - p;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return false;
  s->distance = sqrt(d2);
  s->wi = d / s->distance;
  s->point = l->p0.xyz;
  s->p_error = splat_float3(0.0f); /* the point is exact */
  s->normal = splat_float3(0.0f);
  s->pdf = 1.0f;
  s->delta = true;
  *d2_out = d2;
  return true;
}

/* Light from infinitely far (the environment, a directional light) arriving
 * at p along -wi, `bounds` the scene's bounding sphere (xyz centre, w
 * radius): the shadow ray aims at a point past that sphere along wi
 * (nothing beyond it can occlude), a distance that scales with the scene. */
inline void sample_from_infinity(float4 bounds, float3 p, float3 wi, LightSample* s) {
  s->wi = wi;
  s->distance = 2.0f * (length(bounds.xyz - p) + bounds.w) + 1.0f;
  s->point = p + s->distance * wi;
  s->p_error = splat_float3(0.0f);
  s->normal = splat_float3(0.0f);
}

/* A photon from infinitely far, arriving from direction wi, through the
 * disk of sphere `target` (xyz centre, w radius) that faces wi, at `point`
 * of the unit disk (z = 0: the type's emission_point): it starts that
 * disk's point moved back along wi past the scene's bounding sphere
 * `bounds` (so that everything in the scene may stop it) and travels
 * along -wi. Returns the disk's area pi r^2, what its flux is per unit
 * irradiance. */
inline float start_from_infinity(float4 bounds, float4 target, float3 wi, float3 point, float3* origin,
                                 float3* dir) {
  float3 t, b;
  frame_from_normal(wi, &t, &b);
  const float back = length(target.xyz - bounds.xyz) + bounds.w + target.w;
  *origin = target.xyz + back * wi + target.w * (point.x * t + point.y * b);
  *dir = -wi;
  return M_PI_F * target.w * target.w;
}

/* An area light's unguided photon: the side (both of a two-sided
 * emitter), a cosine-distributed direction over it, and the flux
 * Le * area * pi * sides. */
inline float3 emit_area_light(__global const Light* l, float3 point, float3 p_error, float3 n, float2 u, float u_side,
                              float3* origin, float3* dir) {
  float sides = 1.0f;
  if (l->flags & LIGHT_TWO_SIDED) {
    sides = 2.0f;
    if (u_side < 0.5f) n = -n;
  }
  float3 t, b;
  frame_from_normal(n, &t, &b);
  *dir = frame_to_world(sample_cosine_hemisphere(u), t, b, n);
  *origin = spawn_ray_origin(point, p_error, n, *dir); /* off the light's own surface */
  return l->emitted.xyz * (l->emitted.w * M_PI_F * sides);
}

/* An area light's photon along a given direction with density pdf:
 * Le |cos| A / pdf (nothing behind a one-sided emitter: *dir becomes zero,
 * which the traversal rejects without visiting a node, ray_traceable). */
inline float3 area_light_emitted_toward(__global const Light* l, float3 point, float3 p_error, float3 n, float3* dir,
                                        float pdf, float3* origin) {
  const float cosine = dot(*dir, n);
  const float weight = (l->flags & LIGHT_TWO_SIDED) ? fabs(cosine) : fmax(cosine, 0.0f);
  *origin = spawn_ray_origin(point, p_error, cosine < 0.0f ? -n : n, *dir);
  const float3 flux = l->emitted.xyz * (l->emitted.w * weight / pdf);
  if (!(weight > 0.0f)) *dir = splat_float3(0.0f);
  return flux;
}

/* The functions every area light type writes alike, from its
 * <type>_light_emission_point: next-event estimation toward a point drawn
 * uniformly by area (lights that sample the solid angle they subtend
 * define their own), its radiance as phong's intensity, and the photon emission
 * of emit_area_light / area_light_emitted_toward. */
#define AREA_LIGHT_SAMPLE_BY_AREA(type)                                                                  \
  inline bool type##_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {      \
    float3 p_error, n_l;                                                                                \
    const float3 q = type##_light_emission_point(l, u, &p_error, &n_l);                                 \
    return sample_area_light_point(l, p, q, p_error, n_l, s);                                           \
  }
#define AREA_LIGHT_EMISSION(type)                                                                        \
  inline float3 type##_light_intensity_toward(__global const Light* l, float3 w) {                     \
    (void)w;                                                                                            \
    return l->emitted.xyz;                                                                              \
  }                                                                                                     \
  inline float3 type##_light_emit(__global const Light* l, float3 point, float3 p_error, float3 n,      \
                                  float2 u, float u_side, float3* origin, float3* dir) {                \
    return emit_area_light(l, point, p_error, n, u, u_side, origin, dir);                               \
  }                                                                                                     \
  inline float3 type##_light_emitted_toward(__global const Light* l, float3 point, float3 p_error,     \
                                            float3 n, float3* dir, float pdf, float3* origin) {         \
    return area_light_emitted_toward(l, point, p_error, n, dir, pdf, origin);                           \
  }

#endif /* CAUSTICA_LIB_LIGHTS_LIGHT_COMMON_H */
