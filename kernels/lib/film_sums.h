#line 2 "kernels/lib/film_sums.h"
/* The film's fixed point (shared/types.h, FILM_FRACTION_BITS) both ways:
 * a contribution into a 128-bit integer (lib/film.h adds it to the pass in
 * progress), and a 128-bit sum (accumulate_film_pass.cl) back to a float.
 * Compiled for the device, which converts sums before a read (4 bytes a
 * value cross to the host, not 16), and through shared/compat.h for the
 * host, so the two round alike and the host tests the conversions.
 *
 * Rules: both directions round once, to nearest, ties to even, from the
 * exact value. A float is m * 2^e with a 24-bit m, so into fixed point it
 * is m shifted by e + FILM_FRACTION_BITS, exact from 2^-20 up; a sum
 * becomes the low word alone when the high word is 0, otherwise its top 64
 * bits with a sticky bit for the rest (far below float's 24 bits, so it
 * rounds them as the whole value would), scaled back exactly. */
#ifndef CAUSTICA_LIB_FILM_SUMS_H
#define CAUSTICA_LIB_FILM_SUMS_H
#include "shared/types.h"

/* v (finite, >= 0, at most FILM_MAX_CONTRIBUTION) in fixed point, as low and
 * high words: m * 2^shift for v = m * 2^(exponent - 150). */
CS_DEVICE void film_fixed_from_float(float v, ulong* low, ulong* high) {
  /* Below 2^20 (nearly every contribution) the value fits the low word:
   * v * 2^44 is exact (a power of two), and one conversion rounds it to
   * nearest, ties to even, as the general case below does. */
  if (v < 0x1p20f) {
#ifdef __OPENCL_C_VERSION__
    *low = convert_ulong_rte(v * 0x1p44f);
#else
    *low = (ulong)std::nearbyint((double)v * 0x1p44);
#endif
    *high = 0ul;
    return;
  }
  const uint bits = as_uint(v);
  const int exponent = (int)(bits >> 23);
  *low = 0ul;
  *high = 0ul;
  if (exponent == 0) return; /* zero and subnormals (< 2^-126): far below 2^-45 */
  const ulong m = (ulong)((bits & 0x7fffffu) | 0x800000u);
  const int shift = exponent - 150 + FILM_FRACTION_BITS;
  if (shift >= 64) {
    *high = m << (shift - 64);
  } else if (shift > 0) {
    *low = m << shift;
    *high = m >> (64 - shift);
  } else if (shift == 0) {
    *low = m;
  } else if (shift > -25) { /* m < 2^24: from 25 bits dropped on it rounds to 0 */
    const int drop = -shift;
    const ulong kept = m >> drop, rest = m & ((1ul << drop) - 1ul), halfway = 1ul << (drop - 1);
    *low = kept + ((rest > halfway || (rest == halfway && (kept & 1ul))) ? 1ul : 0ul);
  }
}

/* A 128-bit fixed-point sum as the nearest float. */
CS_DEVICE float film_sum_to_float(ulong low, ulong high) {
  float value;
  if (high == 0ul) {
    value = (float)low;
  } else {
    const uint drop = 64u - (uint)clz(high); /* 1 to 64 low bits do not fit */
    ulong top = drop == 64u ? high : (high << (64u - drop)) | (low >> drop);
    const ulong rest = drop == 64u ? low : low & ((1ul << drop) - 1ul);
    if (rest != 0ul) top |= 1ul;
    value = ldexp((float)top, (int)drop);
  }
  /* A power of two: exact (>= 2^-44, never subnormal), and a product, not
   * ldexp's call (on the host a library call per value: most of the time
   * a whole film took to convert). */
  return value * (1.0f / (float)(1ul << FILM_FRACTION_BITS));
}

#endif
