#line 2 "kernels/lib/film.h"
/* Adding to the film's pass in progress (the fixed point of shared/types.h).
 *
 * Rules: a contribution is a 128-bit integer (lib/film_sums.h) added with
 * 64-bit integer atomics: the low word first, whose value before the add
 * says whether it wrapped, then the high word with that carry. Integer
 * addition is associative and the carries total floor(low words' sum /
 * 2^64) whatever the order, so the pass does not depend on the order in
 * which work-items finish (same bits on any device, thread count or
 * work-group size). The high word is touched only by values of 2^20 and
 * more and by carries. Nothing is converted silently: a NaN/Inf or negative
 * component is dropped and counted, one above FILM_MAX_CONTRIBUTION is
 * clamped and counted, a positive one that rounds to 0 is counted
 * (FILM_COUNT_*); the host reports the counts. accumulate_film_pass.cl adds
 * a finished pass to the accumulated passes, each pixel on its own. */
#ifndef CAUSTICA_LIB_FILM_H
#define CAUSTICA_LIB_FILM_H

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#include "lib/film_sums.h"

/* film: the low words of every channel value (three a pixel), then their
 * high words from film_high_offset on: the words nearly every add touches
 * are as dense as a 64-bit film's (a path tracer's shadow stage was 30%
 * slower with low and high interleaved). */
#define FILM_PARAMS \
  __global ulong* restrict film, volatile __global uint* restrict film_counters, uint film_high_offset
#define FILM_ARGS film, film_counters, film_high_offset

/* Bit tests instead of isnan/isinf/signbit: they survive -cl-fast-relaxed-math. */
inline void film_add_value(__global ulong* value, uint high_offset, float v, volatile __global uint* counters) {
  const uint bits = as_uint(v);
  if ((bits & 0x7f800000u) == 0x7f800000u) {
    atomic_inc(&counters[FILM_COUNT_NONFINITE]);
    return;
  }
  if (bits & 0x80000000u) {
    if (bits != 0x80000000u) atomic_inc(&counters[FILM_COUNT_NEGATIVE]); /* -0 is zero */
    return;
  }
  if (bits == 0u) return;
  if (v > FILM_MAX_CONTRIBUTION) {
    atomic_inc(&counters[FILM_COUNT_CLAMPED]);
    v = FILM_MAX_CONTRIBUTION;
  }
  ulong low, high;
  film_fixed_from_float(v, &low, &high);
  if (low != 0ul) {
    const ulong before = atom_add(value, low);
    if (before + low < before) high += 1ul; /* the low word wrapped */
  } else if (high == 0ul) {
    atomic_inc(&counters[FILM_COUNT_UNDERFLOW]);
    return;
  }
  if (high != 0ul) atom_add(value + high_offset, high);
}

inline void film_add(FILM_PARAMS, uint pixel, float3 value) {
  __global ulong* at = film + 3ul * pixel;
  film_add_value(at, film_high_offset, value.x, film_counters);
  film_add_value(at + 1, film_high_offset, value.y, film_counters);
  film_add_value(at + 2, film_high_offset, value.z, film_counters);
}

/* The auxiliary passes (HAS_AUX_PASSES: the denoiser's and compositors'):
 * FILM_AUX_CHANNELS values a pixel from film_aux_offset on (after every
 * pixel's three colour values), summed exactly as the colour is, so that
 * their means are per-pixel sample means too. A normal component n in
 * [-1, 1] is stored as (n + 1) / 2, which the film's non-negative sums
 * hold; the mean decodes as 2 m - 1 (the encoding is affine, so the mean
 * of the encoded values is the encoded mean), which holds only if every
 * sample adds its surface exactly once: at its first rough vertex, or, where
 * its path ends before one, as no surface (albedo 0, normal 0). Its depth
 * is added once, at its first vertex. Albedo is clamped to [0, 1] (what
 * the denoiser takes), depth to FILM_AUX_MAX_DEPTH. */
#define FILM_AUX_CHANNELS 7u /* albedo rgb, normal xyz (encoded), depth */
#define FILM_AUX_MAX_DEPTH 1e12f
inline void film_add_aux_surface(FILM_PARAMS, uint film_aux_offset, uint pixel, float3 albedo, float3 normal) {
  __global ulong* at = film + (ulong)film_aux_offset + (ulong)FILM_AUX_CHANNELS * pixel;
  const float3 a = clamp(albedo, 0.0f, 1.0f), encoded = clamp(normal * 0.5f + 0.5f, 0.0f, 1.0f);
  film_add_value(at, film_high_offset, a.x, film_counters);
  film_add_value(at + 1, film_high_offset, a.y, film_counters);
  film_add_value(at + 2, film_high_offset, a.z, film_counters);
  film_add_value(at + 3, film_high_offset, encoded.x, film_counters);
  film_add_value(at + 4, film_high_offset, encoded.y, film_counters);
  film_add_value(at + 5, film_high_offset, encoded.z, film_counters);
}
inline void film_add_aux_depth(FILM_PARAMS, uint film_aux_offset, uint pixel, float depth) {
  __global ulong* at = film + (ulong)film_aux_offset + (ulong)FILM_AUX_CHANNELS * pixel;
  film_add_value(at + 6, film_high_offset, fmin(depth, FILM_AUX_MAX_DEPTH), film_counters);
}
#endif
