// The light tree (issue 42): a binary tree over every light with a
// position, built on the host and traversed on the device
// (kernels/lib/light_tree.h says how it is sampled and what a node holds).
//
// Rules: each leaf holds one light; a node's bounds, power and emission
// cone bound everything below it (power summed, boxes and cones united; a
// cone is bounded about its lights' mean axis, so each light costs a few
// multiplications rather than trigonometry). A split is chosen among 12
// buckets of the light centroids along each axis by pbrt-v4's cost: power
// x the cone's solid-angle measure M_omega x the box's surface area,
// weighed against the box's aspect along the axis. Nodes are laid out depth
// first; every split is a stable partition, so the same lights in the same
// order give the same tree, bit for bit. Below depth 40 splits fall back to
// halves by count, which keeps every trail within 64 levels for up to
// 2^24 lights. Lights at infinity (directional, environment) are not in it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/lights/light_types.h"

namespace caustica {

// --light-sampler: how next-event estimation picks a light. Tree: the
// light tree (the positioned lights', under a root that picks it or the
// lights at infinity by power); Power: one CDF by power (the photon pass
// always emits so); Uniform: every light alike (what Mitsuba 3 does by
// default: comparisons); Auto: the tree where the scene has more than
// kLightTreeThreshold lights, else power (the session decides).
enum class LightSampler { Auto, Tree, Power, Uniform };
LightSampler parse_light_sampler(const std::string& name);  // auto | tree | power | uniform
const char* light_sampler_name(LightSampler sampler);
// Measured (docs/many_lights.md, with the normal term): at 4 lights the
// tree's error at equal time is 0.58x the CDF's in a room and 0.22x in
// Sponza, from 16 lights 0.2-0.7x; at 1 light they are the same image; 2
// and 3 (the Cornell box's light is 2 triangles side by side) are left
// to the CDF, whose pick the tree's would match there at a walk's cost.
// Above this many lights the tree is the default.
inline constexpr size_t kLightTreeThreshold = 3;

struct LightTree {
  std::vector<LightTreeNode> nodes;   // depth first; empty without lights in it
  std::vector<LightTreeTrail> trails;  // per light of the table: its path (depth 0 and no bits when not in the tree)
  std::vector<uint32_t> lights;        // the table's lights in the tree, in leaf order
  double build_ms = 0.0;
  int max_depth = 0;
};

// The tree over `lights` (the light table's, Light.kind naming each type)
// with these powers (the table's sampling weights: an emission texture's
// mean included); lights whose type has no tree bounds, or no power, are
// left out.
LightTree build_light_tree(const std::vector<Light>& lights, const std::vector<float>& power);

// What next-event estimation walks (lib/light_tree.h) for `sampler` (Tree
// or Uniform): Tree: build_light_tree's tree of the positioned lights, and
// where the table also has lights at infinity, a root (LIGHT_TREE_BY_POWER)
// whose first child is theirs (picked by power) and second the tree;
// Uniform: every light of the table under nodes that pick by count.
LightTree build_sampling_tree(const std::vector<Light>& lights, const std::vector<float>& power, LightSampler sampler);

}  // namespace caustica
