#line 2 "kernels/lib/lights.h"
/* The light registry: every light type, and the dispatch from a Light
 * (shared/types.h) to its type's functions.
 *
 * Rules: a light type is one file here (lib/lights/<type>_light.h, its six
 * functions described in lib/lights/light_common.h), one file on the host
 * (host/lights/<type>_light.cpp: reading it from a scene file, its power,
 * phong's stand-in, its geometry) and one line in each registry: the
 * LIGHT_TYPES row below, with its #include beside it, and the host's
 * (host/lights/light_types.cpp). Kind numbers are the rows' order, so a new
 * type goes last. The third column is the type's class: 0 a delta light,
 * 1 an area light, whose sampling programs of point-lit scenes leave out
 * (HAS_AREA_LIGHTS=0, shared/feature_flags.h), 2 the environment, whose
 * functions also read the `environment` buffer (its image and sampling
 * distribution: every dispatch below takes it, a one-element dummy
 * without one) and which programs of scenes without a sky leave out
 * (HAS_ENVIRONMENT=0).
 * Densities are per unit solid angle at the shading point and include the
 * probability of picking the light; a delta light's density is that
 * probability alone, and MIS never weights it. */
#ifndef CAUSTICA_LIB_LIGHTS_H
#define CAUSTICA_LIB_LIGHTS_H

#include "lib/lights/point_light.h"
#include "lib/lights/rect_light.h"
#include "lib/lights/sphere_light.h"
#include "lib/lights/triangle_light.h"
#include "lib/lights/cylinder_light.h"
#include "lib/lights/spot_light.h"
#include "lib/lights/environment_light.h"
#include "lib/lights/directional_light.h"
#include "lib/alpha_cutout.h"

/*                 kind            type      class */
#define LIGHT_TYPES(X)                       \
  X(LIGHT_POINT,    point,    0)             \
  X(LIGHT_RECT,     rect,     1)             \
  X(LIGHT_SPHERE,   sphere,   1)             \
  X(LIGHT_TRIANGLE, triangle, 1)             \
  X(LIGHT_CYLINDER, cylinder, 1)             \
  X(LIGHT_SPOT,     spot,     0)             \
  X(LIGHT_ENVIRONMENT, environment, 2)       \
  X(LIGHT_DIRECTIONAL, directional, 0)

#define LIGHT_KIND_ENUM(kind, type, class_) kind,
enum { LIGHT_TYPES(LIGHT_KIND_ENUM) LIGHT_KIND_COUNT };
#undef LIGHT_KIND_ENUM

/* Whether a type's sampling is compiled: area types only in programs whose
 * scene has area lights, the environment only where the scene has one (the
 * constant false drops their code). */
#define LIGHT_TYPE_SAMPLED_0 1
#if HAS_AREA_LIGHTS
#define LIGHT_TYPE_SAMPLED_1 1
#else
#define LIGHT_TYPE_SAMPLED_1 0
#endif
#if HAS_ENVIRONMENT
#define LIGHT_TYPE_SAMPLED_2 1
#else
#define LIGHT_TYPE_SAMPLED_2 0
#endif
#define LIGHT_TYPE_SAMPLED(cls) LIGHT_TYPE_SAMPLED_##cls
/* The arguments a type's functions take before the light's own. */
#define LIGHT_DATA_ARGS_0
#define LIGHT_DATA_ARGS_1
#define LIGHT_DATA_ARGS_2 environment,
#define LIGHT_DATA_ARGS(cls) LIGHT_DATA_ARGS_##cls

/* The light whose prefix probability first exceeds u (binary search). */
inline uint pick_light(__global const Light* lights, uint count, float u) {
  uint lo = 0u, hi = count - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) / 2u;
    if (u < lights[mid].select_cdf) hi = mid;
    else lo = mid + 1u;
  }
  return lo;
}

/* Next-event estimation toward light l, picked with pick_probability. */
inline bool sample_light(__global const Light* l, __global const float* environment, float pick_probability, float3 p, float2 u, LightSample* s) {
  s->delta = false;
  bool found = false;
  switch (l->kind) {
#define LIGHT_SAMPLE_CASE(kind, type, class_) \
  case kind: found = LIGHT_TYPE_SAMPLED(class_) && type##_light_sample(LIGHT_DATA_ARGS(class_) l, p, u, s); break;
    LIGHT_TYPES(LIGHT_SAMPLE_CASE)
#undef LIGHT_SAMPLE_CASE
  }
  if (!found) return false;
  s->pdf = pick_probability * s->pdf;
  return s->pdf > 0.0f;
}

/* What sample_light's density would have been for the direction wi from p
 * that reached point q of light l (a BSDF-sampled ray's hit). */
inline float light_pdf(__global const Light* l, __global const float* environment, float pick_probability, float3 p, float3 q, float3 wi) {
  float pdf = 0.0f;
  switch (l->kind) {
#define LIGHT_PDF_CASE(kind, type, class_) \
  case kind: pdf = LIGHT_TYPE_SAMPLED(class_) ? type##_light_pdf(LIGHT_DATA_ARGS(class_) l, p, q, wi) : 0.0f; break;
    LIGHT_TYPES(LIGHT_PDF_CASE)
#undef LIGHT_PDF_CASE
  }
  return pick_probability * pdf;
}

/* A delta light's intensity along w (phong). */
inline float3 light_intensity_toward(__global const Light* l, __global const float* environment, float3 w) {
  switch (l->kind) {
#define LIGHT_INTENSITY_CASE(kind, type, class_) \
  case kind: return type##_light_intensity_toward(LIGHT_DATA_ARGS(class_) l, w);
    LIGHT_TYPES(LIGHT_INTENSITY_CASE)
#undef LIGHT_INTENSITY_CASE
  }
  return splat_float3(0.0f);
}

/* A photon's start on light l: the point, its error bound, the normal. */
inline float3 light_emission_point(__global const Light* l, __global const float* environment, float2 u, float3* p_error, float3* n) {
  switch (l->kind) {
#define LIGHT_POINT_CASE(kind, type, class_) \
  case kind: return type##_light_emission_point(LIGHT_DATA_ARGS(class_) l, u, p_error, n);
    LIGHT_TYPES(LIGHT_POINT_CASE)
#undef LIGHT_POINT_CASE
  }
  *p_error = *n = splat_float3(0.0f);
  return l->p0.xyz;
}

/* An unguided photon from that point: its origin, direction and flux. */
inline float3 light_emit(__global const Light* l, __global const float* environment, float3 point, float3 p_error, float3 n, float2 u, float u_side,
                         float3* origin, float3* dir) {
  switch (l->kind) {
#define LIGHT_EMIT_CASE(kind, type, class_) \
  case kind: return type##_light_emit(LIGHT_DATA_ARGS(class_) l, point, p_error, n, u, u_side, origin, dir);
    LIGHT_TYPES(LIGHT_EMIT_CASE)
#undef LIGHT_EMIT_CASE
  }
  *origin = point;
  *dir = splat_float3(0.0f);
  return splat_float3(0.0f);
}

/* The flux of a photon sent from that point along *dir with density pdf. */
inline float3 light_emitted_toward(__global const Light* l, __global const float* environment, float3 point, float3 p_error, float3 n, float3* dir,
                                   float pdf, float3* origin) {
  switch (l->kind) {
#define LIGHT_TOWARD_CASE(kind, type, class_) \
  case kind: return type##_light_emitted_toward(LIGHT_DATA_ARGS(class_) l, point, p_error, n, dir, pdf, origin);
    LIGHT_TYPES(LIGHT_TOWARD_CASE)
#undef LIGHT_TOWARD_CASE
  }
  *origin = point;
  *dir = splat_float3(0.0f);
  return splat_float3(0.0f);
}

/* What scales light l's radiance at the point u places on it (the u given
 * to sample_light or light_emission_point), and so a shadow ray's radiance
 * and a photon's flux: its emission texture's texel for a textured triangle
 * light (LIGHT_EMISSION_TEXTURE, lights/triangle_light.h), times how much
 * of a cut-out triangle is there (LIGHT_ALPHA: 0 in a MASK's holes, alpha
 * on a BLEND; lib/alpha_cutout.h), else 1. The densities are unchanged
 * (the point is still uniform by area), so light sampling and a ray that
 * hits the emitter (only where it is there) estimate the same light. */
inline float3 light_emission_texel(__global const Light* l, __global const TriangleShading* triangle_shading,
                                   __global const Texture* textures, __global const ushort* texels,
                                   __global const TriangleAlpha* triangle_alpha,
                                   __global const ushort* alpha_texels, float2 u) {
  float3 scale = splat_float3(1.0f);
#if HAS_TEXTURES
  if (l->flags & LIGHT_EMISSION_TEXTURE)
    scale = triangle_light_texel(l, triangle_shading, textures, (__global const half*)texels, u);
#endif
#if HAS_ALPHA_CUTOUTS
  if (l->flags & LIGHT_ALPHA) {
    const float2 bc = triangle_light_barycentrics(u);
    scale *= alpha_coverage(triangle_alpha, alpha_texels, as_uint(l->p0.w), bc.x, bc.y);
  }
#endif
  (void)l;
  (void)triangle_shading;
  (void)textures;
  (void)texels;
  (void)triangle_alpha;
  (void)alpha_texels;
  (void)u;
  return scale;
}

#endif /* CAUSTICA_LIB_LIGHTS_H */
