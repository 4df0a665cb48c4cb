#line 2 "kernels/lib/lights/environment_light.h"
/* Environment light (the scene's "environment": an equirectangular image as
 * the sky). Light: p0.xyz = centre and p0.w = radius of a sphere bounding
 * the scene (photons start on a disk of it; shadow rays aim past it);
 * p1.x = the map's integral of luminance over solid angle (the host's
 * power); emitted.xyz = the largest texel radiance (per channel).
 * The image and its sampling distribution are the `environment` buffer
 * (host/lights/environment_light.cpp writes it), laid out in floats:
 *   [0] width w, [1] height h, [2] pdf scale w h / sum f, [3] 1 when f
 *   weighs texels by luminance (importance sampling), 0 when not (f = sin t
 *   alone: uniform over the sphere, "importance": false, for comparisons);
 *   [4..6], [8..10], [12..14]: the rows of M, world -> map (M = R^T for the
 *   scene's "rotate" R);
 *   ENV_HEADER_FLOATS on: w h texels of 4 floats (linear rgb radiance times
 *   the intensity, unused), row-major from the top row; then the marginal
 *   CDF over rows (h + 1 floats, 0 ... 1); then one conditional CDF per row
 *   (w + 1 floats each).
 * Convention (scenes/FORMAT.md): map direction d = (sin t sin p, cos t,
 * sin t cos p) with t = pi v (v = 0 the top row: +y is up) and
 * p = 2 pi (u - 1/2): the image's centre looks along +z and its right half
 * toward +x. A texel is constant over its solid angle (no filtering), so
 * the sampling density f = luminance x sin(t at the row's centre) is
 * proportional to what is seen, up to the sin t across a row; the
 * solid-angle density is f scale / (2 pi^2 sin t). Functions as in
 * lights/light_common.h, with the buffer first (the registry passes it to
 * the types of its class 2). */
#ifndef CAUSTICA_LIB_LIGHTS_ENVIRONMENT_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_ENVIRONMENT_LIGHT_H

#include "lib/lights/light_common.h"

#define ENV_HEADER_FLOATS 16u

inline uint environment_width(__global const float* env) { return (uint)env[0]; }
inline uint environment_height(__global const float* env) { return (uint)env[1]; }

inline float3 environment_to_map(__global const float* env, float3 w) {
  return make_float3(env[4] * w.x + env[5] * w.y + env[6] * w.z, env[8] * w.x + env[9] * w.y + env[10] * w.z,
                  env[12] * w.x + env[13] * w.y + env[14] * w.z);
}
inline float3 environment_to_world(__global const float* env, float3 m) {
  return make_float3(env[4] * m.x + env[8] * m.y + env[12] * m.z, env[5] * m.x + env[9] * m.y + env[13] * m.z,
                  env[6] * m.x + env[10] * m.y + env[14] * m.z);
}

/* The texel seen along world direction w, and sin t of w. */
inline uint environment_texel_of(__global const float* env, float3 w, float* sin_theta) {
  const float3 m = environment_to_map(env, w);
  const uint width = environment_width(env), height = environment_height(env);
  const float cos_theta = clamp(m.y, -1.0f, 1.0f);
  *sin_theta = sqrt(fmax(0.0f, 1.0f - cos_theta * cos_theta));
  const float u = 0.5f + atan2(m.x, m.z) * (0.5f * M_1_PI_F), v = acos(cos_theta) * M_1_PI_F;
  const uint x = min((uint)fmax(0.0f, u * (float)width), width - 1u);
  const uint y = min((uint)fmax(0.0f, v * (float)height), height - 1u);
  return y * width + x;
}

inline float3 environment_texel(__global const float* env, uint texel) {
  __global const float* t = env + ENV_HEADER_FLOATS + 4u * texel;
  return make_float3(t[0], t[1], t[2]);
}

/* The sky's radiance arriving along -w (seen looking along w): misses. */
inline float3 environment_radiance(__global const float* env, float3 w) {
  float sin_theta;
  return environment_texel(env, environment_texel_of(env, w, &sin_theta));
}

/* Solid-angle density of sampling texel `texel` along a direction at sin t. */
inline float environment_texel_pdf(__global const float* env, uint texel, float sin_theta) {
  if (!(sin_theta > 0.0f)) return 0.0f;
  const uint width = environment_width(env), height = environment_height(env);
  const float3 c = environment_texel(env, texel);
  const float luminance = env[3] > 0.0f ? 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z : 1.0f;
  const float row_sin = sin(M_PI_F * ((float)(texel / width) + 0.5f) / (float)height);
  return luminance * row_sin * env[2] / (2.0f * M_PI_F * M_PI_F * sin_theta);
}

/* The largest i < n with cdf[i] <= u: bins of zero width are never chosen. */
inline uint environment_cdf_bin(__global const float* cdf, uint n, float u) {
  uint lo = 0u, hi = n - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi + 1u) / 2u;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid - 1u;
  }
  return lo;
}

/* Where u falls within bin i, in [0, 1). */
inline float environment_within(__global const float* cdf, uint i, float u) {
  const float width = cdf[i + 1u] - cdf[i];
  const float t = width > 0.0f ? (u - cdf[i]) / width : 0.5f;
  return clamp(t, 0.0f, 0.99999994f);
}

/* A direction drawn from the map's distribution (marginal over rows, then
 * the row's conditional), and its solid-angle density. */
inline float3 environment_sample_direction(__global const float* env, float2 u, float* pdf) {
  const uint width = environment_width(env), height = environment_height(env);
  __global const float* marginal = env + ENV_HEADER_FLOATS + 4u * width * height;
  const uint y = environment_cdf_bin(marginal, height, u.y);
  /* (y + t) rounds to h for t just below 1 in the last row: v stays inside
   * (0, 1), where sin t > 0 and the density is defined. */
  const float v = clamp(((float)y + environment_within(marginal, y, u.y)) / (float)height, 1e-7f, 0.99999994f);
  __global const float* row = marginal + (height + 1u) + y * (width + 1u);
  const uint x = environment_cdf_bin(row, width, u.x);
  const float uu = ((float)x + environment_within(row, x, u.x)) / (float)width;
  float cos_phi;
  const float sin_phi = sincos(2.0f * M_PI_F * (uu - 0.5f), &cos_phi);
  float cos_theta;
  const float sin_theta = sincos(M_PI_F * v, &cos_theta);
  *pdf = environment_texel_pdf(env, y * width + x, sin_theta);
  return normalize(environment_to_world(env, make_float3(sin_theta * sin_phi, cos_theta, sin_theta * cos_phi)));
}

/* Next-event estimation: the shadow ray aims at a point past the bounding
 * sphere along the sampled direction (nothing beyond it can occlude). */
inline bool environment_light_sample(__global const float* env, __global const Light* l, float3 p, float2 u,
                                     LightSample* s) {
  float pdf;
  const float3 wi = environment_sample_direction(env, u, &pdf);
  if (!(pdf > 0.0f)) return false;
  sample_from_infinity(l->p0, p, wi, s);
  s->radiance = environment_radiance(env, wi);
  s->pdf = pdf;
  return true;
}

inline float environment_light_pdf(__global const float* env, __global const Light* l, float3 p, float3 q,
                                   float3 wi) {
  (void)l; (void)p; (void)q;
  float sin_theta;
  const uint texel = environment_texel_of(env, wi, &sin_theta);
  return environment_texel_pdf(env, texel, sin_theta);
}

/* Phong has no stand-in for it (it is seen at misses instead). */
inline float3 environment_light_intensity_toward(__global const float* env, __global const Light* l, float3 w) {
  (void)env; (void)l; (void)w;
  return splat_float3(0.0f);
}

/* A photon's start: a point of the unit disk (z = 0), placed across the
 * bounding sphere once emit has drawn the direction. */
inline float3 environment_light_emission_point(__global const float* env, __global const Light* l, float2 u,
                                               float3* p_error, float3* n) {
  (void)env; (void)l;
  *p_error = splat_float3(0.0f);
  *n = splat_float3(0.0f);
  const float2 d = sample_concentric_disk(u);
  return make_float3(d.x, d.y, 0.0f);
}

/* A photon arriving from direction wi (drawn from the map) through the
 * disk of sphere `target` (xyz centre, w radius) facing wi, from outside
 * the scene (start_from_infinity, light_common.h); flux
 * L(wi) pi r^2 / pdf(wi). `target` is the scene's bounding sphere, or
 * (guided emission, emit_photons.cl) one around the casters: every line
 * along -wi that meets a caster crosses its disk. */
inline float3 environment_emit_through(__global const float* env, __global const Light* l, float4 target,
                                       float3 point, float2 u, float3* origin, float3* dir) {
  float pdf;
  const float3 wi = environment_sample_direction(env, u, &pdf);
  const float area = start_from_infinity(l->p0, target, wi, point, origin, dir);
  if (!(pdf > 0.0f)) {
    *dir = splat_float3(0.0f);
    return splat_float3(0.0f);
  }
  return environment_radiance(env, wi) * (area / pdf);
}

inline float3 environment_light_emit(__global const float* env, __global const Light* l, float3 point,
                                     float3 p_error, float3 n, float2 u, float u_side, float3* origin, float3* dir) {
  (void)p_error; (void)n; (void)u_side;
  return environment_emit_through(env, l, l->p0, point, u, origin, dir);
}

/* Guided emission aims from a point at the casters; the sky has no point,
 * so emit_photons guides its photons through environment_emit_through
 * instead (this is never called). */
inline float3 environment_light_emitted_toward(__global const float* env, __global const Light* l, float3 point,
                                               float3 p_error, float3 n, float3* dir, float pdf, float3* origin) {
  (void)env; (void)l; (void)p_error; (void)n; (void)pdf;
  *origin = point;
  *dir = splat_float3(0.0f);
  return splat_float3(0.0f);
}

#endif /* CAUSTICA_LIB_LIGHTS_ENVIRONMENT_LIGHT_H */
