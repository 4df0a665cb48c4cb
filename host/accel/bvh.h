// Bounding volume hierarchy over every primitive of a scene (spheres,
// cylinders and triangles in one tree), in the flattened depth-first layout
// the kernels traverse (BvhNode in kernels/shared/types.h,
// kernels/lib/bvh_traverse.h).
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Deepest leaf the builder produces: the traversal stack (BVH_STACK_SIZE in
// bvh_traverse.h) holds at most one entry per level.
constexpr int kBvhMaxDepth = 64;

struct BvhBuildOptions {
  int max_leaf_size = 4;  // nodes with more primitives are split while depth allows
  int bins = 16;          // SAH candidate planes per axis = bins - 1
  // Depth limit, clamped to kBvhMaxDepth. Near it the builder switches from
  // SAH to median splits (lower values exist to test that fallback).
  int max_depth = kBvhMaxDepth;
};

struct Bvh {
  std::vector<BvhNode> nodes;       // nodes[0] is the root
  std::vector<uint32_t> prim_refs;  // (type << 30) | index, in leaf order
  double build_ms = 0;
  double sah_cost = 0;  // traversal cost 1, intersection cost 1, areas relative to the root
  int max_depth = 0;    // edges from the root to the deepest leaf
};

// Binned SAH build; O(n log n). An empty scene gives one empty leaf whose
// box is inverted (lo = +1e18, hi = -1e18) so every ray misses it.
Bvh build_bvh(const Scene& scene, const BvhBuildOptions& options = {});

}  // namespace caustica
