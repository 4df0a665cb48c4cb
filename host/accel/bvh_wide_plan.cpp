// The cost plan of the wide-BVH collapse: the dynamic program of Ylitie,
// Karras & Laine (2017) over the binary tree (see CollapsePlan in
// bvh_wide_internal.h). Every node is planned from its children's plans.
#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "host/accel/bvh_wide_internal.h"

namespace caustica::wide_detail {
namespace {

class Planner {
 public:
  Planner(const Bvh& bvh, bool duplicates, const WideBvhOptions& options)
      : bvh_(bvh), duplicates_(duplicates), options_(options) {}

  // Plans every node bottom-up. Subtrees occupy contiguous index ranges in
  // the depth-first layout and a node's plan depends on its children's
  // only, so disjoint subtrees are planned on all threads, and then the few
  // nodes above them, deepest first: the same plans as one backward sweep.
  CollapsePlan run() {
    const size_t n = bvh_.nodes.size();
    // Triangles (distinct) and other references under each node. With
    // spatial-split duplicates, subtrees small enough to be a leaf keep
    // their sorted triangle refs, merged from their children's, so that
    // the distinct count costs no more than the merge.
    tris_.assign(n, 0);
    others_.assign(n, 0);
    small_.assign(duplicates_ ? n : 0, {});
    plan_.nodes.resize(n);  // every entry is written by plan_node
    const bvh_detail::Workers workers(bvh_detail::resolve_threads(options_.threads));
    std::vector<std::pair<size_t, size_t>> ranges{{0, n}};  // [root, end) of subtrees
    std::vector<size_t> above;                              // nodes above them
    constexpr size_t kRangesPerThread = 8, kMinRange = 4096;
    while (workers.threads() > 1 && ranges.size() < kRangesPerThread * size_t(workers.threads())) {
      const auto largest = std::max_element(ranges.begin(), ranges.end(), [](const auto& a, const auto& b) {
        return a.second - a.first < b.second - b.first;
      });
      const auto [root, end] = *largest;
      if (end - root < kMinRange || bvh_.nodes[root].count > 0) break;
      above.push_back(root);
      const size_t right = bvh_.nodes[root].offset;
      *largest = {root + 1, right};
      ranges.emplace_back(right, end);
    }
    workers.for_each_dynamic(ranges.size(), [&](size_t r) {
      for (size_t i = ranges[r].second; i-- > ranges[r].first;) plan_node(i);
    });
    std::sort(above.rbegin(), above.rend());
    for (size_t i : above) plan_node(i);
    std::vector<uint32_t>().swap(tris_);
    std::vector<uint32_t>().swap(others_);
    std::vector<std::vector<uint32_t>>().swap(small_);
    return std::move(plan_);
  }

 private:
  // Leaf cost of a binary subtree in blocks (triangle blocks plus other
  // references) and the child slots that leaf takes; slots 0 when the
  // subtree cannot be one leaf slot (both kinds, or too many references).
  // `distinct`: its triangles without spatial-split duplicates.
  void leaf_shape(int64_t node, uint32_t distinct, uint32_t others, double* blocks, int* slots) const {
    const uint32_t max_tris = WIDE_LEAF_MAX_COUNT * kBlockLanes;
    if (bvh_.nodes[node].count > 0) {  // a binary leaf is always a leaf, in as many chunks as it needs
      *blocks = double((distinct + kBlockLanes - 1) / kBlockLanes + others);
      *slots = static_cast<int>((distinct + max_tris - 1) / max_tris +
                                (others + WIDE_LEAF_MAX_COUNT - 1) / WIDE_LEAF_MAX_COUNT);
      return;
    }
    *slots = 0;
    if (others == 0 && distinct <= max_tris) {
      *blocks = double((distinct + kBlockLanes - 1) / kBlockLanes);
      *slots = 1;
    } else if (distinct == 0 && others <= WIDE_LEAF_MAX_COUNT) {
      *blocks = double(others);
      *slots = 1;
    }
  }

  void plan_node(size_t i) {
    const size_t max_tris = WIDE_LEAF_MAX_COUNT * kBlockLanes;
    const bool duplicates = duplicates_;
    std::vector<uint32_t>& tris = tris_;
    std::vector<uint32_t>& others = others_;
    std::vector<std::vector<uint32_t>>& small = small_;
    {
      const BvhNode& node = bvh_.nodes[i];
      CollapsePlan::Node& p = plan_.nodes[i];
      const double area = node_box(node).half_area();
      if (node.count > 0) {
        for (uint32_t k = node.offset; k < node.offset + node.count; ++k) {
          const uint32_t ref = bvh_.prim_refs[k];
          if (!is_triangle(ref)) {
            ++others[i];
          } else if (duplicates) {
            small[i].push_back(ref);
          } else {
            ++tris[i];
          }
        }
        if (duplicates) {
          std::sort(small[i].begin(), small[i].end());
          small[i].erase(std::unique(small[i].begin(), small[i].end()), small[i].end());
          tris[i] = static_cast<uint32_t>(small[i].size());
        }
      } else {
        const size_t l = i + 1, r = node.offset;
        others[i] = others[l] + others[r];
        if (!duplicates) {
          tris[i] = tris[l] + tris[r];
        } else if (small[l].size() + small[r].size() <= 2 * max_tris && tris[l] <= max_tris && tris[r] <= max_tris &&
                   tris[l] == small[l].size() && tris[r] == small[r].size()) {
          std::vector<uint32_t>& merged = small[i];
          merged.resize(small[l].size() + small[r].size());
          merged.erase(std::set_union(small[l].begin(), small[l].end(), small[r].begin(), small[r].end(),
                                      merged.begin()),
                       merged.end());
          tris[i] = static_cast<uint32_t>(merged.size());
        } else {
          tris[i] = tris[l] + tris[r];  // an upper bound, only ever compared with max_tris
        }
        if (duplicates) {
          std::vector<uint32_t>().swap(small[l]);
          std::vector<uint32_t>().swap(small[r]);
          if (tris[i] > max_tris) std::vector<uint32_t>().swap(small[i]);
        }
      }
      double blocks = 0.0;
      int leaf_slots = 0;
      leaf_shape(static_cast<int64_t>(i), tris[i], others[i], &blocks, &leaf_slots);
      const double leaf_cost = area * options_.block_cost * blocks;
      if (node.count > 0) {
        for (int s = 1; s <= WIDE_WIDTH; ++s) {
          const bool fits = s >= leaf_slots;
          p.cost[s - 1] = leaf_cost + (fits ? 0.0 : area * options_.node_cost);
          p.choice[s - 1] = fits ? CollapsePlan::kLeaf : CollapsePlan::kNode;
        }
        p.split = 0;
        return;
      }
      const CollapsePlan::Node& pl = plan_.nodes[i + 1];
      const CollapsePlan::Node& pr = plan_.nodes[node.offset];
      double spread[WIDE_WIDTH + 1];  // spread[s]: best cost of the two children in s slots
      int8_t spread_k[WIDE_WIDTH + 1];
      for (int s = 2; s <= WIDE_WIDTH; ++s) {
        spread[s] = std::numeric_limits<double>::infinity();
        spread_k[s] = 1;
        for (int k = 1; k < s; ++k) {
          const double c = pl.cost[k - 1] + pr.cost[s - k - 1];
          if (c < spread[s]) {
            spread[s] = c;
            spread_k[s] = static_cast<int8_t>(k);
          }
        }
      }
      p.split = spread_k[WIDE_WIDTH];
      const double as_node = area * options_.node_cost + spread[WIDE_WIDTH];
      const bool leaf = leaf_slots == 1 && leaf_cost <= as_node;
      p.cost[0] = leaf ? leaf_cost : as_node;
      p.choice[0] = leaf ? CollapsePlan::kLeaf : CollapsePlan::kNode;
      for (int s = 2; s <= WIDE_WIDTH; ++s) {
        const bool fewer = p.cost[s - 2] <= spread[s];
        p.cost[s - 1] = fewer ? p.cost[s - 2] : spread[s];
        p.choice[s - 1] = fewer ? CollapsePlan::kFewer : spread_k[s];
      }
    }
  }

  const Bvh& bvh_;
  const bool duplicates_;
  const WideBvhOptions& options_;
  CollapsePlan plan_;
  std::vector<uint32_t> tris_, others_;  // distinct triangles and other references under each node
  std::vector<std::vector<uint32_t>> small_;
};

}  // namespace

CollapsePlan plan_collapse(const Bvh& bvh, bool duplicates, const WideBvhOptions& options) {
  return Planner(bvh, duplicates, options).run();
}

}  // namespace caustica::wide_detail
