#line 2 "kernels/film/accumulate_film_pass.cl"
/* Film stage: a finished pass, or a wave of passes (128-bit fixed point,
 * lib/film.h), is added to the accumulated passes, and the pass buffer is
 * cleared for the next.
 * The accumulated sums are 128-bit integers in the same fixed point (two
 * ulongs, low word first): integer addition is associative, so the sums do
 * not depend on how passes were grouped into waves, in which order they were
 * added, or in how many processes (a state file's, another rank's: issue
 * 23). Values of 1e12 (2^84 in fixed point) can be added 2^44 times. The
 * host reads them as floats (read_film_sums, Film::mean). One work-item per
 * channel value. Layout of `passes`: the combined sum of every sample at 0;
 * with FilmAccumulate.half_offset != FILM_PASS_ABSENT, there (in values) the
 * pixel's half: the sum of its samples since the latest restart. A pixel
 * with n samples whose wave adds k restarts its half when [n, n + k) holds a
 * power of two (n > 0), so with every pixel alike (waves never cross a power
 * of two: host/render/pass_driver.cpp) the half is [P, N), P the largest
 * power of two below N: at N = 2^k the second half of the sequence, which
 * with Sobol-Burley samples is a well-stratified set of its own (odd passes
 * are not, and made the estimate ~2x high). A pixel of an adaptive wave may
 * cross one: its half then starts at n, the wave's first sample
 * (lib/wave_samples.h's rule, which the host film shares). */

#include "lib/film.h"
#include "lib/wave_samples.h"

/* sum (two ulongs at *sum, low first) += (low, high) */
inline void add_to_sum128(__global ulong* sum, ulong low, ulong high) {
  const ulong sum_low = sum[0] + low;
  sum[1] += high + (sum_low < low ? 1ul : 0ul); /* with the carry */
  sum[0] = sum_low;
}

__kernel void accumulate_film_pass(__global ulong* restrict film, __global ulong* restrict passes,
                                   FilmAccumulate params, __global const uint* restrict pixel_spp,
                                   __global const uint* restrict wave_spp) {
  const uint i = get_global_id(0);
  if (i >= params.value_count) return;
  /* three colour values a pixel, then (aux passes) FILM_AUX_CHANNELS */
  const uint pixel = i < params.colour_values ? i / 3u : (i - params.colour_values) / FILM_AUX_CHANNELS;
  const uint n = params.per_pixel ? pixel_spp[pixel] : params.pass_index;
  const uint k = params.per_pixel ? wave_spp[pixel] : params.pass_count;
  if (k == 0u) return; /* not in this wave: its pass value is zero */
  const ulong low = film[i], high = film[params.value_count + i]; /* lib/film.h's layout */
  add_to_sum128(&passes[2ul * i], low, high);
  if (params.half_offset != FILM_PASS_ABSENT && n > 0u) {
    __global ulong* half_sum = &passes[2ul * ((ulong)params.half_offset + i)];
    if (film_half_restarts(n, k)) half_sum[0] = half_sum[1] = 0ul;
    add_to_sum128(half_sum, low, high);
  }
  film[i] = film[params.value_count + i] = 0ul;
}

/* Before the host reads them: value_count sums from `offset` (in values) as
 * floats, one work-item each. */
__kernel void read_film_sums(__global const ulong* restrict passes, __global float* restrict values,
                             uint value_count, uint offset) {
  const uint i = get_global_id(0);
  if (i >= value_count) return;
  const ulong at = 2ul * ((ulong)offset + i);
  values[i] = film_sum_to_float(passes[at], passes[at + 1ul]);
}

/* The low words of value_count sums from `offset` (in values) into `low`
 * from low_offset, and a flag set where a sum does not fit them: a high
 * word, or a low word above most_low (the most that the processes of a
 * render shared among them add in 64 bits; Film::summed_band sums the low
 * words alone then). */
__kernel void read_film_low_words(__global const ulong* restrict passes, __global ulong* restrict low,
                                  volatile __global uint* restrict wide, uint value_count, uint offset,
                                  uint low_offset, ulong most_low) {
  const uint i = get_global_id(0);
  if (i >= value_count) return;
  const ulong at = 2ul * ((ulong)offset + i);
  const ulong l = passes[at], h = passes[at + 1ul];
  low[(ulong)low_offset + i] = l;
  if (h != 0ul || l > most_low) atomic_or(wide, 1u);
}
