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
 * so the two weights of a light sample sum to 1 to within about 1e-6. The
 * tree is asked without the surface normal, which a ray that reaches an
 * emitter no longer knows: the pmf MIS reads must be the one sampling
 * used. */
#ifndef CAUSTICA_LIB_LIGHT_PICK_H
#define CAUSTICA_LIB_LIGHT_PICK_H

#include "lib/light_tree.h"
#include "lib/lights.h"
#include "lib/scene_buffers.h"

/* A light for next-event estimation at p from u; *probability its pick
 * probability. */
inline uint pick_light_at(const SceneBuffers* s, uint light_count, float3 p, float u, float* probability) {
#if HAS_LIGHT_TREE
  (void)light_count;
  return light_tree_sample(s->light_tree_nodes, p, make_float3(0.0f, 0.0f, 0.0f), u, probability);
#else
  (void)p;
  const uint li = pick_light(s->lights, light_count, u);
  *probability = s->lights[li].select_probability;
  return li;
#endif
}

/* The probability that pick_light_at(p) picks light li. */
inline float light_pick_probability(const SceneBuffers* s, uint li, float3 p) {
#if HAS_LIGHT_TREE
  return light_tree_pmf(s->light_tree_nodes, s->light_tree_trails[li], p, make_float3(0.0f, 0.0f, 0.0f));
#else
  (void)p;
  return s->lights[li].select_probability;
#endif
}

#endif
