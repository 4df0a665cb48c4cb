#line 2 "kernels/lib/shading_point.h"
/* The point every shader reads: surface_at's geometry (lib/surface.h), then
 * what the hit triangle's vertex data and its material's maps make of it:
 * the vertex colour (HAS_VERTEX_COLOURS) and the normal map's shading
 * normal (HAS_NORMAL_MAPS, lib/normal_map.h). The path tracer, the photon
 * pass and phong all take their point here, so a photon scatters off the
 * normal a path sees. Without either flag this is surface_at itself. */
#ifndef CAUSTICA_LIB_SHADING_POINT_H
#define CAUSTICA_LIB_SHADING_POINT_H

#include "lib/normal_map.h"
#include "lib/surface.h"

#if HAS_VERTEX_COLOURS
/* Triangle `index`'s vertex colours at barycentrics (b1, b2), rgb. */
inline float3 triangle_vertex_colour(__global const TriangleColours* triangle_colours, uint index, float b1, float b2) {
  __global const half* c = (__global const half*)triangle_colours[index].rgba;
  const float3 c0 = vload_half4(0, c).xyz, c1 = vload_half4(1, c).xyz, c2 = vload_half4(2, c).xyz;
  return c0 + b1 * (c1 - c0) + b2 * (c2 - c0);
}
#endif

CS_DEVICE SurfacePoint shading_point_at(SCENE_SURFACE_PARAMS, Hit hit, float3 o, float3 d) {
  SurfacePoint sp = surface_at(spheres, cylinders, triangles, triangle_shading, hit, o, d);
  (void)triangle_tangents;
  (void)triangle_colours;
  (void)materials;
  (void)textures;
  (void)texels;
  (void)environment;
#if HAS_VERTEX_COLOURS
  if (prim_ref_type(hit.prim) == PRIM_TRIANGLE)
    sp.colour = clamp(triangle_vertex_colour(triangle_colours, prim_ref_index(hit.prim), hit.u, hit.v), 0.0f, 1.0f);
#endif
#if HAS_NORMAL_MAPS
  apply_normal_map(&sp, &materials[sp.material], triangle_tangents, textures, texels, hit, d);
#endif
  return sp;
}

#endif /* CAUSTICA_LIB_SHADING_POINT_H */
