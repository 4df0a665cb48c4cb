// Pieces of the wide-BVH collapse shared by host/accel/bvh_wide.cpp (the
// layout and its emission) and host/accel/bvh_wide_plan.cpp (the cost
// plan). Not part of the public API.
#pragma once

#include <cstddef>
#include <cstdint>

#include "host/accel/bulk_allocator.h"
#include "host/accel/bvh_internal.h"
#include "host/accel/bvh_wide.h"

namespace caustica::wide_detail {

constexpr size_t kBlockLanes = 4;  // triangles per TriangleBlock4

inline bvh_detail::Box node_box(const BvhNode& n) {
  bvh_detail::Box b;
  b.lo = {n.lo_x, n.lo_y, n.lo_z};
  b.hi = {n.hi_x, n.hi_y, n.hi_z};
  return b;
}

inline bool is_triangle(uint32_t ref) { return (ref >> PRIM_TYPE_SHIFT) == PRIM_TRIANGLE; }

// The cost-driven collapse (WideBvhOptions::Collapse::Sah), one entry per
// binary node. cost[i - 1]: the least SAH cost of representing the binary
// subtree by at most i child slots of the wide node above it; choice[i - 1]
// says how: kLeaf (all its references as leaf chunks), kNode (one wide node
// of its own), kFewer (as with i - 1 slots) or k > 0 (k slots for the left
// child, i - k for the right). split: the left child's share of the eight
// slots when the subtree is a wide node.
struct CollapsePlan {
  static constexpr int8_t kFewer = 0, kLeaf = -1, kNode = -2;
  struct Node {
    double cost[WIDE_WIDTH];
    int8_t choice[WIDE_WIDTH];
    int8_t split;  // no initialiser: the plan is sized without writing it
  };
  BulkVector<Node> nodes;
};

// Plans every node of `bvh` bottom-up, on options.threads threads (the plan
// does not depend on them). `duplicates`: spatial splits referenced some
// primitive twice, so leaves count distinct triangles.
CollapsePlan plan_collapse(const Bvh& bvh, bool duplicates, const WideBvhOptions& options);

}  // namespace caustica::wide_detail
