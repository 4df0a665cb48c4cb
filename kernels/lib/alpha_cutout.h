#line 2 "kernels/lib/alpha_cutout.h"
/* Alpha cut-outs in the traversal (glTF alphaMode MASK and BLEND;
 * compiled only with HAS_ALPHA_CUTOUTS, so scenes without them traverse
 * exactly as before).
 *
 * Rules: a triangle's candidate hit is dropped where its alpha says the
 * surface is not there, before the hit competes for closest (a cut-out
 * never hides what lies behind it) and before an any-hit query counts it
 * as an occluder: camera and bounce rays (trace_closest), shadow rays
 * (trace_any) and photons (trace_closest in the photon pass) see one mask.
 * alpha = TriangleAlpha.factor x the image's fourth channel at the hit's
 * texture coordinates (types.h). MASK keeps the hit where alpha >= cutoff.
 * BLEND keeps it with probability alpha (stochastic transparency): a
 * surface that blends a fraction alpha of its own light with 1 - alpha of
 * what lies behind is estimated without bias by keeping it a fraction
 * alpha of the time, and a shadow ray passes it with probability
 * 1 - alpha, which is its transmittance. The choice is a hash of the
 * triangle and the ray's bits: the same ray makes the same choice in any
 * query, on any device, in any order of traversal, and different rays
 * (other samples, other bounces) choose independently. */
#ifndef CAUSTICA_LIB_ALPHA_CUTOUT_H
#define CAUSTICA_LIB_ALPHA_CUTOUT_H

#include "lib/geometry.h"
#include "lib/rng.h"
#include "lib/texture.h"
#include "shared/types.h"

#if HAS_ALPHA_CUTOUTS

/* Triangle `index`'s alpha at barycentrics (u, v) (its record's mode is
 * not ALPHA_OPAQUE). */
inline float triangle_alpha_at(__global const TriangleAlpha* a, __global const ushort* alpha_texels, float u,
                               float v) {
  float alpha = a->factor;
#if HAS_TEXTURES
  if (a->offset != ALPHA_NO_IMAGE) {
    const float2 uv0 = make_float2(a->u0, a->v0);
    const float2 uv = uv0 + u * (make_float2(a->u1, a->v1) - uv0) + v * (make_float2(a->u2, a->v2) - uv0);
    alpha *= texture_image_sample((__global const half*)alpha_texels, a->offset, (int)a->width, (int)a->height,
                                  a->sampling, uv).w;
  }
#else
  (void)alpha_texels;
  (void)u;
  (void)v;
#endif
  return alpha;
}

/* How much of triangle `index` is there at barycentrics (u, v), on
 * average over the rays that reach it: 1 or 0 for a MASK, alpha for a
 * BLEND (the emission a cut-out light sends from that point). */
inline float alpha_coverage(__global const TriangleAlpha* triangle_alpha, __global const ushort* alpha_texels,
                            uint index, float u, float v) {
  __global const TriangleAlpha* a = &triangle_alpha[index];
  if (a->mode == ALPHA_OPAQUE) return 1.0f;
  const float alpha = triangle_alpha_at(a, alpha_texels, u, v);
  return a->mode == ALPHA_MASK ? (alpha >= a->cutoff ? 1.0f : 0.0f) : clamp(alpha, 0.0f, 1.0f);
}

/* Whether triangle `index` is there at barycentrics (u, v) of the ray (o, d). */
inline bool alpha_keeps_hit(__global const TriangleAlpha* triangle_alpha, __global const ushort* alpha_texels,
                            uint index, float u, float v, float3 o, float3 d) {
  __global const TriangleAlpha* a = &triangle_alpha[index];
  if (a->mode == ALPHA_OPAQUE) return true;
  const float alpha = triangle_alpha_at(a, alpha_texels, u, v);
  if (a->mode == ALPHA_MASK) return alpha >= a->cutoff;
  const uint ray_key = hash3(hash3(as_uint(o.x), as_uint(o.y), as_uint(o.z)), hash3(as_uint(d.x), as_uint(d.y), as_uint(d.z)),
                             0xA1F4u);
  return random_float(ray_key, index) < alpha;
}

/* The lanes of a triangle block's hits (u, v per lane) that alpha keeps. */
inline int4 alpha_kept_lanes(__global const TriangleBlock4* block, int4 lanes, float4 u, float4 v,
                             __global const TriangleAlpha* triangle_alpha, __global const ushort* alpha_texels,
                             float3 o, float3 d) {
  int l[4], out[4];
  float tu[4], tv[4];
  vstore4(lanes, 0, l);
  vstore4(u, 0, tu);
  vstore4(v, 0, tv);
  for (int i = 0; i < 4; ++i)
    out[i] = l[i] && alpha_keeps_hit(triangle_alpha, alpha_texels, prim_ref_index(block->ref[i]), tu[i], tv[i], o, d)
                 ? -1
                 : 0;
  return vload4(0, out);
}

#endif /* HAS_ALPHA_CUTOUTS */

#endif /* CAUSTICA_LIB_ALPHA_CUTOUT_H */
