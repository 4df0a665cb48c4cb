#line 2 "kernels/lib/light_pick.h"
/* Which light next-event estimation samples from a shading point, and the
 * probability MIS reads for the light a BSDF-sampled ray found: one CDF by
 * power (Light.select_probability, select_cdf: host/lights/light_table.h),
 * or, in programs built with HAS_LIGHT_TREE (--light-sampler tree or
 * uniform), the light tree walked from the point (lib/light_tree.h).
 *
 * Rules: both ask at the point the path leaves the surface from: next-event
 * estimation at the shading point, MIS at the continuation ray's origin,
 * which is that point moved off the surface by its error bound (a few ulps
 * of its coordinates): the tree's importance is continuous in the point,
 * so the two weights of a light sample sum to 1 to within about 1e-6. Both
 * ask with the same normal, to the bit: next-event estimation packs the
 * vertex's normal (light_tree_normal_at), weighs lights with its unpacked
 * value, and the continuation carries the packed one (PathRecord
 * .light_normal) to where its ray meets an emitter. The normal is the
 * geometric one turned toward the path at an opaque surface (no light
 * below it is sampled or followed: shade_path_vertex.h), and none at
 * glass, which takes light from both sides. */
#ifndef CAUSTICA_LIB_LIGHT_PICK_H
#define CAUSTICA_LIB_LIGHT_PICK_H

#include "lib/bsdf.h"
#include "lib/light_normal.h"
#include "lib/light_tree.h"
#include "lib/lights.h"
#include "lib/scene_buffers.h"

/* The normal the tree weighs lights with at a vertex, packed (see the
 * rules); LIGHT_NORMAL_NONE without the tree, where nothing reads it. */
inline uint light_tree_normal_at(const Bsdf* bsdf, const ShadingFrame* frame) {
#if HAS_LIGHT_TREE
  return bsdf->kind == BSDF_DIELECTRIC ? LIGHT_NORMAL_NONE : light_normal_pack(frame->ng);
#else
  (void)bsdf;
  (void)frame;
  return LIGHT_NORMAL_NONE;
#endif
}

/* A light for next-event estimation at p (packed normal light_normal)
 * from u; *probability its pick probability. */
inline uint pick_light_at(const SceneBuffers* s, uint light_count, float3 p, uint light_normal, float u,
                          float* probability) {
#if HAS_LIGHT_TREE
  (void)light_count;
  return light_tree_sample(s->light_tree_nodes, p, light_normal_unpack(light_normal), u, probability);
#else
  (void)p;
  (void)light_normal;
  const uint li = pick_light(s->lights, light_count, u);
  *probability = s->lights[li].select_probability;
  return li;
#endif
}

/* The probability that pick_light_at(p, light_normal) picks light li. */
inline float light_pick_probability(const SceneBuffers* s, uint li, float3 p, uint light_normal) {
#if HAS_LIGHT_TREE
  return light_tree_pmf(s->light_tree_nodes, s->light_tree_trails[li], p, light_normal_unpack(light_normal));
#else
  (void)p;
  (void)light_normal;
  return s->lights[li].select_probability;
#endif
}

#endif
