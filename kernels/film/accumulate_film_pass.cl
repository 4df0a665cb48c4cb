#line 2 "kernels/film/accumulate_film_pass.cl"
/* Film stage: a finished pass, or a wave of passes (fixed point, lib/film.h),
 * becomes floats added to the accumulated passes, and the pass buffer is
 * cleared for the next.
 * One work-item per channel value, each adding on its own in pass order, so
 * the accumulated film is deterministic as well. Layout of `passes` (floats):
 * the combined sum of every sample at 0; with FilmAccumulate.half_offset !=
 * FILM_PASS_ABSENT, there the pixel's half: the sum of its samples since the
 * latest restart. A pixel with n samples whose wave adds k restarts its half
 * when [n, n + k) holds a power of two (n > 0), so with every pixel alike
 * (waves never cross a power of two: host/render/pass_driver.cpp) the half
 * is [P, N), P the largest power of two below N: at N = 2^k the second half
 * of the sequence, which with Sobol-Burley samples is a well-stratified set
 * of its own (odd passes are not, and made the estimate ~2x high). A pixel
 * of an adaptive wave may cross one: its half then starts at n, the wave's
 * first sample (lib/wave_samples.h's rule, which the host film shares). */

#include "lib/wave_samples.h"

__kernel void accumulate_film_pass(__global ulong* restrict film, __global float* restrict passes,
                                   FilmAccumulate params, __global const uint* restrict pixel_spp,
                                   __global const uint* restrict wave_spp) {
  const uint i = get_global_id(0);
  if (i >= params.value_count) return;
  const uint n = params.per_pixel ? pixel_spp[i / 3u] : params.pass_index;
  const uint k = params.per_pixel ? wave_spp[i / 3u] : params.pass_count;
  if (k == 0u) return; /* not in this wave: its pass value is zero */
  /* Rounds once, like the exact value / scale would: scale is a power of two. */
  const float value = convert_float(film[i]) * params.inv_scale;
  passes[i] += value;
  if (params.half_offset != FILM_PASS_ABSENT && n > 0u)
    passes[params.half_offset + i] = (film_half_restarts(n, k) ? 0.0f : passes[params.half_offset + i]) + value;
  film[i] = 0;
}
