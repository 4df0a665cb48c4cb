#line 2 "kernels/lib/film.h"
/* Film accumulation. Contributions are added as 64-bit fixed point with
 * integer atomics: integer addition is associative, so the image does not
 * depend on the order in which work-items finish (same bits on any device,
 * thread count or work-group size). NaN, Inf and negative values never reach
 * the film: they are dropped here, and huge values are clamped. */
#ifndef CAUSTICA_LIB_FILM_H
#define CAUSTICA_LIB_FILM_H

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#include "shared/types.h"

/* Bit test instead of isnan/isinf: it survives -cl-fast-relaxed-math. */
inline float sanitize_contribution(float v) {
  uint bits = as_uint(v);
  if ((bits & 0x7f800000u) == 0x7f800000u) return 0.0f; /* NaN or Inf */
  return clamp(v, 0.0f, FILM_MAX_CONTRIBUTION);
}

inline void film_add(__global ulong* film, uint pixel, float3 value) {
  float r = sanitize_contribution(value.x);
  float g = sanitize_contribution(value.y);
  float b = sanitize_contribution(value.z);
  if (r > 0.0f) atom_add(&film[3 * pixel + 0], (ulong)(r * FILM_FIXED_SCALE + 0.5f));
  if (g > 0.0f) atom_add(&film[3 * pixel + 1], (ulong)(g * FILM_FIXED_SCALE + 0.5f));
  if (b > 0.0f) atom_add(&film[3 * pixel + 2], (ulong)(b * FILM_FIXED_SCALE + 0.5f));
}

#endif
