#line 2 "kernels/lib/scene_buffers.h"
/* The scene as the path tracer's and the photon pass's stages read it: its
 * BVH, primitives, materials, textures, environment and lights, in one
 * struct of pointers that a kernel builds from its parameters
 * (SCENE_BUFFERS_FROM_PARAMS) and hands to the stage functions, instead of
 * a list of fifteen parameters through every call.
 *
 * Rules: the kernel parameters keep these names, which the host binds by
 * name (host/render/device_scene.cpp: bind_scene; the lights' buffers:
 * host/lights/light_table.cpp); a stage function that calls a library
 * function written for parameter lists passes SCENE_GEOMETRY_OF(s) or
 * SCENE_SURFACE_OF(s). The struct lives in private memory and is
 * dissolved into registers by inlining: it costs nothing at run time. */
#ifndef CAUSTICA_LIB_SCENE_BUFFERS_H
#define CAUSTICA_LIB_SCENE_BUFFERS_H

#include "lib/geometry.h"
#include "lib/surface.h"
#include "shared/types.h"

typedef struct {
  __global const BvhNode8* bvh_nodes;
  __global const TriangleBlock4* tri_blocks;
  __global const uint* prim_refs;
  __global const Sphere* spheres;
  __global const Cylinder* cylinders;
  __global const Triangle* triangles;
  __global const TriangleAlpha* triangle_alpha; /* HAS_ALPHA_CUTOUTS */
  __global const ushort* alpha_texels;          /* the texels, for the traversal */
  __global const TriangleShading* triangle_shading;
  __global const TriangleTangents* triangle_tangents; /* HAS_NORMAL_MAPS */
  __global const TriangleColours* triangle_colours;   /* HAS_VERTEX_COLOURS */
  __global const Material* materials;
  __global const Texture* textures;
  __global const ushort* texels;
  __global const float* environment;
  __global const Light* lights;
  /* a primitive's light (LIGHT_NONE: not one), by primitive type */
  __global const uint* light_of_sphere;
  __global const uint* light_of_cylinder;
  __global const uint* light_of_triangle;
  /* the light tree next-event estimation walks (HAS_LIGHT_TREE; lib/light_tree.h) */
  __global const LightTreeNode* light_tree_nodes;
  __global const LightTreeTrail* light_tree_trails;
} SceneBuffers;

#define SCENE_BUFFERS_PARAMS                                                                                  \
  __global const BvhNode8 *restrict bvh_nodes, __global const TriangleBlock4 *restrict tri_blocks,           \
      __global const uint *restrict prim_refs, __global const TriangleAlpha *restrict triangle_alpha,       \
      __global const ushort *restrict alpha_texels, SCENE_SURFACE_PARAMS, __global const Light *restrict lights, \
      __global const uint *restrict light_of_sphere, __global const uint *restrict light_of_cylinder,         \
      __global const uint *restrict light_of_triangle, __global const LightTreeNode *restrict light_tree_nodes, \
      __global const LightTreeTrail *restrict light_tree_trails
#define SCENE_BUFFERS_FROM_PARAMS                                                                                  \
  {bvh_nodes,        tri_blocks,       prim_refs, spheres, cylinders,   triangles,       triangle_alpha,    \
   alpha_texels,      triangle_shading,                                                                   \
   triangle_tangents, triangle_colours, materials, textures, texels,    environment,     lights,            \
   light_of_sphere,   light_of_cylinder, light_of_triangle, light_tree_nodes, light_tree_trails}

#define SCENE_GEOMETRY_OF(s)                                                                                  \
  (s)->bvh_nodes, (s)->tri_blocks, (s)->prim_refs, (s)->spheres, (s)->cylinders, (s)->triangles,              \
      (s)->triangle_alpha, (s)->alpha_texels
#define SCENE_SURFACE_OF(s)                                                                                    \
  (s)->spheres, (s)->cylinders, (s)->triangles, (s)->triangle_shading, (s)->triangle_tangents,               \
      (s)->triangle_colours, (s)->materials, (s)->textures, (s)->texels, (s)->environment

/* The light a hit primitive is (LIGHT_NONE: none). */
inline uint light_of_primitive(const SceneBuffers* s, uint prim) {
  const uint type = prim_ref_type(prim), index = prim_ref_index(prim);
  if (type == PRIM_SPHERE) return s->light_of_sphere[index];
  if (type == PRIM_CYLINDER) return s->light_of_cylinder[index];
  return s->light_of_triangle[index];
}

#endif /* CAUSTICA_LIB_SCENE_BUFFERS_H */
