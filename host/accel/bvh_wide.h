// The 8-wide BVH the kernels traverse (BvhNode8 and TriangleBlock4 in
// kernels/shared/types.h, kernels/lib/bvh_traverse.h), collapsed from the
// binary BVH of bvh.h. PoCL runs each work-item as scalar code, so SIMD has
// to come from inside the work-item: eight child boxes per float8 test and
// four triangles per float4 test, instead of one box or triangle at a time.
#pragma once

#include <cstdint>
#include <vector>

#include "host/accel/bulk_allocator.h"
#include "host/accel/bvh.h"
#include "host/scene/scene.h"

namespace caustica {

// Stack entries the kernels keep per ray (CS_BVH_STACK_SIZE, types.h).
// The traversal stays within it as long as the root's height is below it;
// collapse_bvh refuses deeper trees.
constexpr int kWideStackSize = CS_BVH_STACK_SIZE;

struct WideBvhOptions {
  // Subtrees holding only triangles, at most four of them, become one leaf
  // block: the binned builder splits down to one or two triangles a leaf,
  // and a half-empty block costs as much to test as a full one.
  bool merge_small_subtrees = true;
  // Largest merged subtree. More than one block's worth (4) was tried: it
  // halves the node count but tests more blocks than it saves nodes.
  size_t merge_max_triangles = 4;
  // Which wide tree to make of the binary one. Sah: the dynamic program of
  // Ylitie, Karras & Laine (2017) that picks, for every binary subtree, the
  // cheapest of "one leaf", "one wide node" and "split over up to eight
  // slots", by the SAH with the costs below; leaves may hold several
  // blocks. Greedy: open the largest child until eight (the older rule).
  enum class Collapse { Sah, Greedy };
  Collapse collapse = Collapse::Sah;
  double node_cost = 1.0;   // testing one wide node (eight boxes at once)
  double block_cost = 1.0;  // testing one block of four triangles, or one other primitive
  // Threads that fill the triangle blocks; 0: std::thread::hardware_concurrency().
  // The result does not depend on it.
  int threads = 0;
};

struct WideBvh {
  std::vector<BvhNode8> nodes;  // nodes[0] is the root (an empty scene: all slots empty)
  BulkVector<TriangleBlock4> triangle_blocks;
  std::vector<uint32_t> prim_refs;  // encoded refs of the sphere/cylinder leaves
  int height = 0;                   // BvhNode8::height of the root
  size_t triangle_lanes = 0;        // block lanes holding a distinct triangle (fill statistics)
  size_t leaves = 0;                // leaf child slots
  // SAH cost in Embree's normalisation (its verbose statistics), so the two
  // trees compare directly: the half areas of all inner nodes, and of all
  // leaves times their blocks (or references), over the root's half area.
  double node_sah = 0.0;
  double leaf_sah = 0.0;
  double collapse_ms = 0.0;
};

// Collapses the binary tree by the rule of options.collapse: by default the
// cost-driven dynamic program (Sah above: per binary subtree the cheapest of
// one leaf of up to eight blocks, one wide node, or a split over up to eight
// of the parent's slots); Greedy opens the child with the largest surface
// area until a node has eight. Leaves keep the binary leaves' boxes (clipped
// to their triangles), so the spatial-split boxes of a builder that
// duplicates references stay as tight as built. Throws Error when the result
// exceeds the kernels' limits (node count, stack height).
WideBvh collapse_bvh(const Bvh& bvh, const Scene& scene, const WideBvhOptions& options = {});

}  // namespace caustica
