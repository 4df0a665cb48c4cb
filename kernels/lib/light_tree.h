#line 2 "kernels/lib/light_tree.h"
/* The light tree (issue 42): a light picked for next-event estimation by
 * walking the tree from the root, each step choosing a child in proportion
 * to its importance at the shading point (Conty Estevez and Kulla 2018,
 * "Importance Sampling of Many Lights with Adaptive Tree Splitting";
 * pbrt-v4's BVHLightSampler). host/lights/light_tree.h builds it
 * (LightTreeNode, shared/types.h).
 *
 * Rules: the importance of a node at point p with normal n bounds what its
 * lights can send there: power / distance^2, times the cosine of the
 * smallest angle between the direction to p and the emission cone (widened
 * by the cone the node's box subtends from p), times how far the box's
 * sphere rises above the receiving surface, cos(angle to the normal) +
 * sin(the sphere's half-angle), on the side the normal faces
 * (lib/light_pick.h says which normal). A light's pmf
 * (light_tree_pmf) repeats the sampling's arithmetic along its trail, so it
 * is the exact probability that light_tree_sample picks it from (p, n):
 * MIS reads it for BSDF-sampled hits. Where neither child can light the
 * point the walk goes on by power: every light's pmf is above 0 and they
 * sum to 1. Nodes flagged LIGHT_TREE_BY_POWER pick by power alone: lights
 * at infinity, which have no position, hang under a root that picks them
 * or the positioned lights' tree by power (as Cycles does). Compiled as
 * C++ too (host tests). */
#ifndef CAUSTICA_LIB_LIGHT_TREE_H
#define CAUSTICA_LIB_LIGHT_TREE_H

/* The largest float below 1: where a remapped u must stay. */
#define LIGHT_TREE_ONE_MINUS_EPSILON 0x1.fffffep-1f

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#else
#include "kernels/shared/compat.h"
#include "kernels/shared/types.h"
#endif

/* cos(max(0, a - b)) and sin(max(0, a - b)) from the angles' sines and cosines. */
inline float light_tree_cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
inline float light_tree_sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}

/* What the node's lights can send to p (normal n; zero n: no normal term). */
inline float light_tree_importance(__global const LightTreeNode* node, float3 p, float3 n) {
  const float power = node->bounds_min.w;
  if (!(power > 0.0f)) return 0.0f;
  const float3 lo = node->bounds_min.xyz, hi = node->bounds_max.xyz;
  const float3 centre = 0.5f * (lo + hi), to_p = p - centre, diag = hi - lo;
  const float dist2 = dot(to_p, to_p), radius2 = 0.25f * dot(diag, diag);
  /* Inside the box's sphere every direction is possible; the distance is
   * at least its radius, so a node's importance is invariant to scale. */
  if (!(dist2 > radius2)) return power / fmax(radius2, 1e-30f);
  const float cos_o = node->bounds_max.w;
  const bool has_normal = dot(n, n) > 0.0f;
  /* Lights that emit every way (points, spheres, cylinders, and any node
   * over them): nothing narrows the emission cone (the general form below
   * gives cos_p = 1). */
  if (cos_o <= -1.0f && !has_normal) return power / dist2;
  const float dist = sqrt(dist2);
  float importance = power / dist2;
  if (has_normal) {
    /* One-sided: the receiving surface takes light from the side n faces.
     * cos(angle to n) + sin(the box's half-angle) = (-p.n + r) / d is
     * above 0 exactly where some of the box's sphere is above the surface
     * (where cos(max(0, theta - theta_b)) is), for one square root where
     * that form takes four; 1e-3 of slack (about as many radians at the
     * horizon) for the packed normal's rounding (lib/light_pick.h). A node
     * wholly below the surface gets nothing. */
    const float radius = sqrt(radius2);
    importance *= clamp((radius - dot(to_p, n)) / dist + 1e-3f, 0.0f, 1.0f);
    if (!(importance > 0.0f)) return 0.0f;
  }
  if (cos_o > -1.0f) {
    const float3 wi = to_p / dist;
    const float sin_b2 = radius2 / dist2;
    const float cos_b = sqrt(fmax(0.0f, 1.0f - sin_b2)), sin_b = sqrt(sin_b2);
    float cos_w = dot(node->axis.xyz, wi);
    if (node->flags & LIGHT_TREE_TWO_SIDED) cos_w = fabs(cos_w);
    const float sin_w = sqrt(fmax(0.0f, 1.0f - cos_w * cos_w));
    const float sin_o = node->sin_o;
    const float cos_x = light_tree_cos_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const float sin_x = light_tree_sin_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const float cos_p = light_tree_cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    /* Beyond theta_o + theta_e nothing reaches p (strictly: a spot light's
     * theta_e is 0, and inside its cone cos_p is 1). */
    if (cos_p < node->axis.w) return 0.0f;
    importance *= cos_p;
  }
  return fmax(importance, 0.0f);
}

/* The probability of the first child at an interior node: by importance
 * at (p, n), or, where neither child can light p (a parent's bound is
 * looser than its children's), by power, so that the walk always reaches
 * a leaf and the pmfs of all lights sum to 1. */
inline float light_tree_first_child_probability(__global const LightTreeNode* nodes, uint node, float3 p, float3 n) {
  __global const LightTreeNode* first = &nodes[node + 1u];
  __global const LightTreeNode* second = &nodes[nodes[node].index];
  if (nodes[node].flags & LIGHT_TREE_BY_POWER) return first->bounds_min.w / (first->bounds_min.w + second->bounds_min.w);
  const float i0 = light_tree_importance(first, p, n), i1 = light_tree_importance(second, p, n);
  if (i0 + i1 > 0.0f) return i0 / (i0 + i1);
  return first->bounds_min.w / (first->bounds_min.w + second->bounds_min.w);
}

/* A light for point p with normal n from u in [0, 1); *pmf its
 * probability (above 0: every light has power). */
inline uint light_tree_sample(__global const LightTreeNode* nodes, float3 p, float3 n, float u, float* pmf) {
  uint node = 0u;
  float probability = 1.0f;
  while (!(nodes[node].flags & LIGHT_TREE_LEAF)) {
    const float p0 = light_tree_first_child_probability(nodes, node, p, n);
    if (u < p0) {
      u = fmin(u / p0, LIGHT_TREE_ONE_MINUS_EPSILON);
      probability *= p0;
      node = node + 1u;
    } else {
      const float p1 = 1.0f - p0;
      u = fmin((u - p0) / p1, LIGHT_TREE_ONE_MINUS_EPSILON);
      probability *= p1;
      node = nodes[node].index;
    }
  }
  *pmf = probability;
  return nodes[node].index;
}

/* The probability that light_tree_sample picks the light whose trail is
 * `trail` from (p, n): the same arithmetic, level by level. */
inline float light_tree_pmf(__global const LightTreeNode* nodes, LightTreeTrail trail, float3 p, float3 n) {
  uint node = 0u;
  float probability = 1.0f;
  for (uint level = 0u; level < trail.depth; ++level) {
    const float p0 = light_tree_first_child_probability(nodes, node, p, n);
    const uint second = level < 32u ? (trail.bits_lo >> level) & 1u : (trail.bits_hi >> (level - 32u)) & 1u;
    if (second) {
      probability *= 1.0f - p0;
      node = nodes[node].index;
    } else {
      probability *= p0;
      node = node + 1u;
    }
  }
  return probability;
}

#endif
