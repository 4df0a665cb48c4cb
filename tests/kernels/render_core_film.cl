#line 2 "tests/kernels/render_core_film.cl"
/* tests/test_render_core.cpp's film: film_add from a list of contributions,
 * plus the pass accumulation, in one program that the Film class drives as
 * the integrators do. A kernel because the film is device state: fixed-point
 * atomics into the pass buffer and the accumulate_film_pass stage. */
#include "lib/film.h"
#include "film/accumulate_film_pass.cl"
__kernel void add_contributions(FILM_PARAMS, __global const float4* restrict values,
                                __global const uint* restrict pixels, uint count) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  film_add(FILM_ARGS, pixels[i], values[i].xyz);
}
