#line 2 "kernels/integrator/shade_surface_binary.cl"
/* Stage: binary mode, as the coursework defines it: a pixel whose camera ray
 * hits anything is red, every other pixel black. No materials, lights or
 * secondary rays are read or made. */

#include "lib/film.h"
#include "lib/queue.h"

__kernel void shade_surface_binary(PATH_QUEUE_PARAMS(in), __global const Hit* restrict hits, FILM_PARAMS) {
  const uint i = get_global_id(0);
  if (i >= *in_count) return;
  if (hits[i].prim == PRIM_NONE) return;
  film_add(FILM_ARGS, in_pixel[i], in_throughput[i].xyz * (float3)(1.0f, 0.0f, 0.0f));
}
