#line 2 "kernels/lib/film.h"
/* Adding to the film's pass in progress (FilmParams in shared/types.h).
 *
 * Rules: contributions are 64-bit fixed point added with integer atomics;
 * integer addition is associative, so the pass does not depend on the order
 * in which work-items finish (same bits on any device, thread count or
 * work-group size). Nothing is converted silently: a NaN/Inf or negative
 * component is dropped and counted, one above max_contribution is clamped
 * and counted (FILM_COUNT_*); the host reports the counts. The host turns a
 * finished pass into floats and adds it to the accumulated passes
 * (accumulate_film_pass.cl), each pixel on its own, in pass order. */
#ifndef CAUSTICA_LIB_FILM_H
#define CAUSTICA_LIB_FILM_H

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#include "shared/types.h"

#define FILM_PARAMS                                                                        \
  __global ulong* restrict film, volatile __global uint* restrict film_counters, \
      FilmParams film_params
#define FILM_ARGS film, film_counters, film_params

/* Bit tests instead of isnan/isinf/signbit: they survive -cl-fast-relaxed-math. */
inline ulong film_fixed(float v, volatile __global uint* counters, FilmParams params) {
  const uint bits = as_uint(v);
  if ((bits & 0x7f800000u) == 0x7f800000u) {
    atomic_inc(&counters[FILM_COUNT_NONFINITE]);
    return 0;
  }
  if (bits & 0x80000000u) {
    if (bits != 0x80000000u) atomic_inc(&counters[FILM_COUNT_NEGATIVE]); /* -0 is zero */
    return 0;
  }
  if (v > params.max_contribution) {
    atomic_inc(&counters[FILM_COUNT_CLAMPED]);
    v = params.max_contribution;
  }
  return (ulong)(v * params.scale + 0.5f);
}

inline void film_add(FILM_PARAMS, uint pixel, float3 value) {
  const ulong r = film_fixed(value.x, film_counters, film_params);
  const ulong g = film_fixed(value.y, film_counters, film_params);
  const ulong b = film_fixed(value.z, film_counters, film_params);
  if (r) atom_add(&film[3 * pixel + 0], r);
  if (g) atom_add(&film[3 * pixel + 1], g);
  if (b) atom_add(&film[3 * pixel + 2], b);
}

#endif
