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

#endif
