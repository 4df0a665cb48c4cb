#line 2 "kernels/lib/film_sums.h"
/* The film's accumulated sums (accumulate_film_pass.cl) as floats:
 * compiled for the device, which converts them before a read (4 bytes a
 * value cross to the host, not 16), and through shared/compat.h for the
 * host, so the two round alike.
 *
 * Rules: a sum is a 128-bit integer (low and high words) in the film's
 * fixed point; it becomes the nearest float, ties to even, in one rounding:
 * the low word alone when the high word is 0 (a single pass: the bits the
 * film's float sums had before they were integers), otherwise its top 64
 * bits with a sticky bit for the rest (far below float's 24 bits, so it
 * rounds them as the whole value would), scaled back exactly. */
#ifndef CAUSTICA_LIB_FILM_SUMS_H
#define CAUSTICA_LIB_FILM_SUMS_H
#include "shared/compat.h"

CS_DEVICE float film_sum_to_float(ulong low, ulong high) {
  if (high == 0ul) return (float)low;
  const uint drop = 64u - (uint)clz(high); /* 1 to 64 low bits do not fit */
  ulong top = drop == 64u ? high : (high << (64u - drop)) | (low >> drop);
  const ulong rest = drop == 64u ? low : low & ((1ul << drop) - 1ul);
  if (rest != 0ul) top |= 1ul;
  return ldexp((float)top, (int)drop);
}

#endif
