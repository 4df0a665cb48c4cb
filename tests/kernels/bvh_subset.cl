#line 2 "tests/kernels/bvh_subset.cl"
/* tests/test_bvh.cpp's BvhKernels.CompileForEveryPrimitiveSubset: traversal
 * and surface_at under every subset of the HAS_* primitive flags, none
 * included, must compile (the renderer builds only what the scene needs).
 * Only built, never run: what it checks is the OpenCL compiler's view. */
#include "lib/bvh_traverse.h"
#include "lib/surface.h"
__kernel void k(SCENE_GEOMETRY_PARAMS, __global float4* out) {
  float3 o = (float3)(0.0f), d = (float3)(0.0f, 0.0f, 1.0f);
  Hit h = trace_closest(SCENE_GEOMETRY_ARGS, o, d, 0.0f, RAY_T_FAR);
  SurfacePoint sp = surface_at(spheres, cylinders, triangles, (__global const TriangleShading*)0, h, o, d);
  out[0] = (float4)(sp.position, trace_any(SCENE_GEOMETRY_ARGS, o, d, 0.0f, 1.0f) ? 1.0f : 0.0f);
}
