// Bounding volume hierarchy over every primitive of a scene (spheres,
// cylinders and triangles in one tree), binary and flattened depth first.
// The kernels do not traverse it: collapse_bvh (bvh_wide.h) turns it into
// the 8-wide layout they do; the host trace (host/bench/host_trace.h) walks
// this one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Deepest leaf the builder produces: the host trace's stack holds at most
// one entry per level (CS_BVH_STACK_SIZE, shared with the kernels).
constexpr int kBvhMaxDepth = CS_BVH_STACK_SIZE;

// A binary node, depth-first: an inner node's left child is the next node,
// its right child is `offset`; a leaf (count > 0) owns prim refs
// [offset, offset + count).
struct BvhNode {
  float lo_x, lo_y, lo_z;
  uint32_t offset;
  float hi_x, hi_y, hi_z;
  uint32_t count;
};

struct BvhBuildOptions {
  enum class Quality {
    // Binned SAH over the widest axis only, 8 bins, leaves of up to
    // 2 * max_leaf_size: for scenes so large that build time matters more
    // than trace time.
    Fast,
    // Binned SAH object splits: every primitive in exactly one leaf.
    Sah,
    // SAH object splits plus spatial splits (SBVH, Stich et al. 2009):
    // triangles straddling a split plane may be referenced from both sides
    // with clipped boxes, so a primitive can sit in several leaves and a leaf
    // box need not contain its primitives whole. At most 1.3 references per
    // primitive; spheres and cylinders are never split.
    Spatial,
  };
  // Sah until tests/test_bvh.cpp stops assuming that a default build holds
  // each primitive exactly once, whole (StructureOfRandomScenes), and times
  // a 350k-triangle default build against a bound Spatial nears on a busy
  // machine: flip this together with those tests. Callers that want
  // spatial splits ask for Spatial.
  Quality quality = Quality::Sah;
  int max_leaf_size = 4;  // nodes with more references are split while depth allows
  int bins = 16;          // SAH candidate planes per axis = bins - 1 (Fast uses at most 8)
  // Depth limit, clamped to kBvhMaxDepth. Near it the builder switches from
  // SAH to median splits (lower values exist to test that fallback).
  int max_depth = kBvhMaxDepth;
  // Worker threads; 0: std::thread::hardware_concurrency(). The tree does
  // not depend on it.
  int threads = 0;
};

struct Bvh {
  std::vector<BvhNode> nodes;       // nodes[0] is the root
  std::vector<uint32_t> prim_refs;  // (type << 30) | index, in leaf order
  double build_ms = 0;
  double sah_cost = 0;  // traversal cost 1, intersection cost 1, areas relative to the root
  int max_depth = 0;    // edges from the root to the deepest leaf
  size_t references = 0;  // prim_refs.size(): primitives plus spatial-split duplicates
};

// O(n log n). An empty scene gives one empty leaf whose box is inverted
// (lo = +1e18, hi = -1e18) so every ray misses it.
Bvh build_bvh(const Scene& scene, const BvhBuildOptions& options = {});

}  // namespace caustica
