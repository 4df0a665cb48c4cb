#line 2 "bench/pocl_vectoriser/vertex_loop.cl"
/* The path tracer's vertex (kernels/integrator/shade_surface_path.cl) as
 * PoCL's work-item loop would run it, for vertex_remarks.sh: vertex_once is
 * one work-item's vertex, optimised alone first (PoCL's first -O3 sees the
 * kernel before its work-item loops exist), then inlined into a loop over
 * the paths for LLVM's loop vectoriser. Its outputs go to memory, as values
 * that cross a barrier go to PoCL's context arrays. */
#include "integrator_path.cl"

#define VERTEX_LOOP_PARAMS                                                                                        \
  SCENE_SURFACE_PARAMS, __global const Light *restrict lights, __global const uint *restrict light_of_sphere,      \
      __global const uint *restrict light_of_cylinder, __global const uint *restrict light_of_triangle,           \
      PathParams params, PATH_QUEUE_PARAMS(in), __global const Hit *restrict hits, FILM_PARAMS,                    \
      PATH_QUEUE_PARAMS(next), SHADOW_QUEUE_PARAMS(shadow), __global PathRecord *restrict children,                \
      __global uint *restrict goes_on
#define VERTEX_LOOP_ARGS                                                                                          \
  spheres, cylinders, triangles, triangle_shading, materials, textures, texels, environment, lights,             \
      light_of_sphere, light_of_cylinder, light_of_triangle, params, PATH_QUEUE_ARGS(in), hits, FILM_ARGS,       \
      PATH_QUEUE_ARGS(next), SHADOW_QUEUE_ARGS(shadow), children, goes_on

__attribute__((noinline)) void vertex_once(VERTEX_LOOP_PARAMS, uint i) {
  PathRecord child;
  const bool goes = shade_path_vertex(PATH_VERTEX_ARGS, i, &child);
  goes_on[i] = goes;
  if (goes) children[i] = child;
}

__kernel void vertex_loop(VERTEX_LOOP_PARAMS, uint n) {
  for (uint i = 0; i < n; ++i) vertex_once(VERTEX_LOOP_ARGS, i);
}
