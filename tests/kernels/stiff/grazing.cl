#line 2 "tests/kernels/stiff/grazing.cl"
/* tests/stiff/test_grazing.cpp's device side: one grazing or tangent probe
 * ray per work-item against one primitive (intersect_prim_ref), its t, u, v
 * and primitive back. A kernel because the test is of the device build: the
 * same probes run under the renderer's -cl-fast-relaxed-math and without. */
#include "lib/bvh_traverse.h"
__kernel void probe(__global const float4* rays, uint n, __global const Sphere* spheres,
                    __global const Cylinder* cylinders, __global const Triangle* triangles, uint ref,
                    __global float4* out) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  Hit h = hit_none(RAY_T_FAR);
  intersect_prim_ref(spheres, cylinders, triangles, ref, rays[2 * i].xyz, rays[2 * i + 1].xyz, 0.0f, &h);
  out[i] = (float4)(h.t, h.u, h.v, as_float(h.prim));
}
