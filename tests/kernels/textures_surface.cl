#line 2 "tests/kernels/textures_surface.cl"
/* tests/test_textures.cpp's surface_at queries: per hit (t, u, v, primitive
 * in w's bits) and its ray, the position, geometric and shading normals
 * and texture coordinates. A kernel because the test runs the device build
 * under the renderer's -cl-fast-relaxed-math and without. */
#include "lib/surface.h"

__kernel void surface(__global const float4* hits, __global const float4* origins, __global const float4* dirs,
                      uint count, __global const Sphere* spheres, __global const Cylinder* cylinders,
                      __global const Triangle* triangles, __global const TriangleShading* shading,
                      __global float4* out) {
  uint i = get_global_id(0);
  if (i >= count) return;
  Hit h;
  h.t = hits[i].x;
  h.u = hits[i].y;
  h.v = hits[i].z;
  h.prim = as_uint(hits[i].w);
  SurfacePoint sp = surface_at(spheres, cylinders, triangles, shading, h, origins[i].xyz, dirs[i].xyz);
  out[4 * i] = (float4)(sp.position, 0.0f);
  out[4 * i + 1] = (float4)(sp.normal, 0.0f);
  out[4 * i + 2] = (float4)(sp.shading_normal, 0.0f);
  out[4 * i + 3] = (float4)(sp.uv, 0.0f, 0.0f);
}
