#line 2 "kernels/film/accumulate_film_pass.cl"
/* Film stage: a finished pass, or a wave of passes (fixed point, lib/film.h),
 * becomes floats added to the accumulated passes, and the pass buffer is
 * cleared for the next.
 * One work-item per channel value, each adding on its own in pass order, so
 * the accumulated film is deterministic as well. Layout of `passes` (floats):
 * the combined sum of every pass at 0; with FilmAccumulate.half_offset !=
 * FILM_PASS_ABSENT, there the sum of the passes since the latest power of
 * two, [P, N) for N passes with P the largest power of two below N (the
 * half that error estimation compares against: at N = 2^k it is the second
 * half, which with Sobol-Burley samples is a well-stratified set of its
 * own; odd passes are not, and made the estimate ~2x high). */

#include "shared/types.h"

__kernel void accumulate_film_pass(__global ulong* restrict film, __global float* restrict passes,
                                   FilmAccumulate params) {
  const uint i = get_global_id(0);
  if (i >= params.value_count) return;
  /* Rounds once, like the exact value / scale would: scale is a power of two. */
  const float value = convert_float(film[i]) * params.inv_scale;
  passes[i] += value;
  /* A pass in progress may hold a wave of passes [pass_index, pass_index +
   * pass_count): the host never lets one cross a power of two but at its
   * start (host/render/pass_driver.cpp), so it lies in one half. */
  if (params.half_offset != FILM_PASS_ABSENT && params.pass_index > 0u) {
    const bool starts_half = (params.pass_index & (params.pass_index - 1u)) == 0u; /* a power of two */
    passes[params.half_offset + i] = (starts_half ? 0.0f : passes[params.half_offset + i]) + value;
  }
  film[i] = 0;
}
