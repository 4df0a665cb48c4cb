#line 2 "kernels/lib/texture.h"
/* Texture lookup (the Texture table and texel buffer of types.h).
 *
 * Rules: compiled only with HAS_TEXTURES, so including this costs nothing
 * otherwise. uv first pass through the texture's affine map where it has
 * one (TEXTURE_TRANSFORMED). Each axis then wraps by the texture's mode:
 * repeat (the default: x - floor(x), texel indices wrapped across the
 * border), clamp to edge (x clamped to [0, 1], indices clamped), or
 * mirrored repeat (x folded into [0, 1] with period 2, indices clamped: the
 * edge texel meets its mirror image); any uv (negative, huge, even
 * non-finite) reads inside the texture. v = 0 is the BOTTOM of an image
 * while image row 0, the first in memory, is its top: texel (column i, row
 * j) has its centre at uv ((i + 0.5) / w, 1 - (j + 0.5) / h). Images are
 * filtered bilinearly between the 4 nearest texel centres, or read at the
 * nearest texel (TEXTURE_NEAREST). Checkers: square (floor(u s), floor(v s))
 * has colour2 when the sum of the two is odd, colour1 when even. Results
 * are linear rgb. */
#ifndef CAUSTICA_LIB_TEXTURE_H
#define CAUSTICA_LIB_TEXTURE_H

#if HAS_TEXTURES

#include "shared/types.h"

/* In [0, 1]: 1 itself can come out of the subtraction by rounding (x = -1e-9),
 * which the index wrap below maps back into the texture. fmax drops a NaN. */
inline float texture_wrap_unit(float x) { return fmin(fmax(x - floor(x), 0.0f), 1.0f); }

/* x in [0, 1] by an axis's wrap mode (clamp_bit, mirror_bit of sampling). */
inline float texture_fold(float x, uint sampling, uint clamp_bit, uint mirror_bit) {
  if (sampling & mirror_bit) {
    const float t = x - 2.0f * floor(0.5f * x); /* [0, 2) */
    x = t > 1.0f ? 2.0f - t : t;
  }
  if (sampling & (clamp_bit | mirror_bit)) return fmin(fmax(x, 0.0f), 1.0f); /* fmax drops a NaN */
  return texture_wrap_unit(x);
}

/* i is in [-1, n] for the coordinates texture_fold produces: repeat wraps
 * it across the border, clamp and mirror keep the edge texel; the clamp
 * also keeps garbage from a non-finite uv in bounds. */
inline int texture_wrap_index(int i, int n) {
  i = i < 0 ? i + n : (i >= n ? i - n : i);
  return clamp(i, 0, n - 1);
}
inline int texture_index(int i, int n, bool repeat) { return repeat ? texture_wrap_index(i, n) : clamp(i, 0, n - 1); }

inline float4 texture_texel(__global const half* texels, uint offset, int width, int x, int y) {
  return vload_half4((size_t)offset + (size_t)y * (size_t)width + (size_t)x, texels);
}

/* The image of w x h texels from `offset` at uv (already transformed) by
 * the sampling bits' wrap modes and filter: all four channels (rgb and
 * the image's alpha). */
inline float4 texture_image_sample(__global const half* texels, uint offset, int w, int h, uint sampling, float2 uv) {
  const bool repeat_u = !(sampling & (TEXTURE_CLAMP_U | TEXTURE_MIRROR_U));
  const bool repeat_v = !(sampling & (TEXTURE_CLAMP_V | TEXTURE_MIRROR_V));
  /* Continuous texel coordinates with texel centres on the integers, y
   * counted from the top row. */
  const float fx = texture_fold(uv.x, sampling, TEXTURE_CLAMP_U, TEXTURE_MIRROR_U) * (float)w - 0.5f;
  const float fy = (1.0f - texture_fold(uv.y, sampling, TEXTURE_CLAMP_V, TEXTURE_MIRROR_V)) * (float)h - 0.5f;
  if (sampling & TEXTURE_NEAREST)
    return texture_texel(texels, offset, w, texture_index((int)floor(fx + 0.5f), w, repeat_u),
                         texture_index((int)floor(fy + 0.5f), h, repeat_v));
  const float x0f = floor(fx);
  const float y0f = floor(fy);
  const float tx = fx - x0f;
  const float ty = fy - y0f;
  const int x0 = texture_index((int)x0f, w, repeat_u);
  const int y0 = texture_index((int)y0f, h, repeat_v);
  const int x1 = texture_index((int)x0f + 1, w, repeat_u);
  const int y1 = texture_index((int)y0f + 1, h, repeat_v);
  const float4 row0 = mix(texture_texel(texels, offset, w, x0, y0), texture_texel(texels, offset, w, x1, y0), tx);
  const float4 row1 = mix(texture_texel(texels, offset, w, x0, y1), texture_texel(texels, offset, w, x1, y1), tx);
  return mix(row0, row1, ty);
}

/* index must name an entry of textures (materials hold -1 for "none"). */
float3 texture_lookup(__global const Texture* textures, __global const half* texels, int index, float2 uv) {
  __global const Texture* tex = &textures[index];
  if (tex->kind == TEXTURE_CHECKER) {
    /* Saturating conversion: defined for any float, unlike (int) of 1e30. The
     * parity of a + b is that of a ^ b, which cannot overflow. */
    const int a = convert_int_sat(floor(uv.x * tex->scale));
    const int b = convert_int_sat(floor(uv.y * tex->scale));
    return ((a ^ b) & 1) ? tex->color2.xyz : tex->color1.xyz;
  }
  const uint sampling = tex->sampling;
  if (sampling & TEXTURE_TRANSFORMED)
    uv = (float2)(tex->uv_u.x * uv.x + tex->uv_u.y * uv.y + tex->uv_u.z, tex->uv_v.x * uv.x + tex->uv_v.y * uv.y + tex->uv_v.z);
  return texture_image_sample(texels, tex->offset, (int)tex->width, (int)tex->height, sampling, uv).xyz;
}

#endif /* HAS_TEXTURES */

#endif /* CAUSTICA_LIB_TEXTURE_H */
