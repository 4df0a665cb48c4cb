#include "host/lights/light_tree.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <utility>

#include "host/elapsed.h"
#include "host/error.h"
#include "host/math_constants.h"

namespace caustica {
namespace {

constexpr int kBuckets = 12;
constexpr int kCountSplitDepth = 40;  // from here on, halves by count (light_tree.h)

struct Item {
  LightBounds bounds;
  glm::vec3 centroid;
  float power = 0.0f;
  float sin_o = 0.0f;
  uint32_t light = 0;
};

// The cosine of the smallest cone about `axis` holding the light's cone:
// cos(angle(axis, its axis) + theta_o), -1 where that passes pi.
float cone_cos_about(const glm::vec3& axis, const Item& item) {
  const LightBounds& b = item.bounds;
  if (b.cos_o <= -1.0f) return -1.0f;
  const float c = std::clamp(glm::dot(axis, b.axis), -1.0f, 1.0f);
  if (c < -b.cos_o) return -1.0f;
  const float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
  // Rounded down a little: a bound must not be tighter than the cones it holds.
  return std::max(-1.0f, c * b.cos_o - s * item.sin_o - 1e-6f);
}

// pbrt-v4's orientation measure of a cone (theta_o, theta_e), M_omega =
// 2 pi (1 - cos theta_o) + pi/2 (2 theta_w sin theta_o - cos(theta_o - 2
// theta_w) - 2 theta_o sin theta_o + cos theta_o), theta_w = min(theta_o +
// theta_e, pi). The build evaluates it for every candidate split, so the
// two cases almost every node is in are reduced by hand: surfaces
// (theta_e = pi/2) and spot lights (theta_e = 0).
double cone_measure(float cos_o_f, float cos_e) {
  const double cos_o = std::clamp(double(cos_o_f), -1.0, 1.0);
  const double sin_o = std::sqrt(std::max(0.0, 1.0 - cos_o * cos_o));
  if (cos_e == 0.0f) {
    if (cos_o > 0.0)  // theta_o < pi/2: theta_w = theta_o + pi/2
      return 2.0 * kPi * (1.0 - cos_o) + kPi * kPi / 2.0 * sin_o + kPi * cos_o;
    return 2.0 * kPi * (1.0 - cos_o) + kPi * sin_o * (kPi - std::acos(cos_o));  // theta_w = pi
  }
  if (cos_e == 1.0f) return 2.0 * kPi * (1.0 - cos_o);
  const double theta_o = std::acos(cos_o);
  const double theta_e = std::acos(std::clamp(double(cos_e), -1.0, 1.0));
  const double theta_w = std::min(theta_o + theta_e, kPi);
  return 2.0 * kPi * (1.0 - cos_o) +
         kPi / 2.0 * (2.0 * theta_w * sin_o - std::cos(theta_o - 2.0 * theta_w) - 2.0 * theta_o * sin_o + cos_o);
}

double surface_area(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::dvec3 d = glm::max(glm::dvec3(hi - lo), glm::dvec3(0.0));
  return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// Where a leaf's light sits: its path from the root and the levels to it.
void set_trail(LightTree& tree, uint32_t light, uint64_t bits, int depth) {
  LightTreeTrail& trail = tree.trails[light];
  trail.bits_lo = uint32_t(bits);
  trail.bits_hi = uint32_t(bits >> 32);
  trail.depth = uint32_t(depth);
}

// A union of lights (a bucket, a side of a split): box, power, the cone's
// cosines about the node's axis, sidedness. Only `count` is set up front:
// the first light added sets the rest. (A node's 36 buckets are most of
// the work of the many nodes with few lights.)
struct Union {
  glm::vec3 lo, hi;
  float power, cos_o, cos_e;  // power: enough to compare splits by
  int count = 0;
  void add(const Item& item, float cone_cos) {
    if (count == 0) {
      lo = item.bounds.lo;
      hi = item.bounds.hi;
      power = item.power;
      cos_o = cone_cos;
      cos_e = item.bounds.cos_e;
    } else {
      lo = glm::min(lo, item.bounds.lo);
      hi = glm::max(hi, item.bounds.hi);
      power += item.power;
      cos_o = std::min(cos_o, cone_cos);
      cos_e = std::min(cos_e, item.bounds.cos_e);
    }
    ++count;
  }
  void add(const Union& u) {
    if (u.count == 0) return;
    if (count == 0) {
      *this = u;
      return;
    }
    lo = glm::min(lo, u.lo);
    hi = glm::max(hi, u.hi);
    power += u.power;
    cos_o = std::min(cos_o, u.cos_o);
    cos_e = std::min(cos_e, u.cos_e);
    count += u.count;
  }
  double cost(double aspect) const {
    // A box with no area (lights at one point) still costs by power and cone.
    return count == 0 ? 0.0 : double(power) * cone_measure(cos_o, cos_e) * aspect * std::max(surface_area(lo, hi), 1e-30);
  }
};

// What a node's build needs of its lights before it looks at them one by
// one: everything but the cone about its axis (which is the mean of theirs).
// The root's is summed in a pass of its own; every other node's while its
// parent's split moves its lights (one pass over a node's lights fewer:
// the build is bound by memory traffic).
struct Summary {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  glm::vec3 centroid_lo = lo, centroid_hi = hi, axis_sum{0.0f};
  double power = 0.0;
  float cos_e = 1.0f;
  bool two_sided = false, omni = false;
  void add(const Item& it) {
    lo = glm::min(lo, it.bounds.lo);
    hi = glm::max(hi, it.bounds.hi);
    centroid_lo = glm::min(centroid_lo, it.centroid);
    centroid_hi = glm::max(centroid_hi, it.centroid);
    axis_sum += it.bounds.axis;
    power += it.power;
    cos_e = std::min(cos_e, it.bounds.cos_e);
    two_sided = two_sided || it.bounds.two_sided;
    omni = omni || it.bounds.cos_o <= -1.0f;
  }
};

class Builder {
 public:
  Builder(std::vector<Item>& items, LightTree& tree)
      : items_(items), tree_(tree), scratch_(items.size()) {}

  // The whole tree at `node` with trail (bits, depth); returns its depth.
  int build_root(uint32_t node, uint64_t bits, int depth) {
    Summary all;
    for (const Item& it : items_) all.add(it);
    return build(0, items_.size(), all, node, bits, depth);
  }

 private:
  // Builds the subtree of items [start, end) (summed up in `sum`) at
  // `node`, whose trail is (bits, depth); returns the deepest level below.
  int build(size_t start, size_t end, const Summary& sum, uint32_t node, uint64_t bits, int depth) {
    LightTreeNode& out = tree_.nodes[node];
    out = LightTreeNode{};
    const float axis_length = glm::length(sum.axis_sum);
    const glm::vec3 axis = axis_length > 1e-6f ? sum.axis_sum / axis_length : glm::vec3(0.0f, 0.0f, 1.0f);
    const bool cone = !(sum.omni || !(axis_length > 1e-6f));
    out.bounds_min = to_float4(sum.lo, float(sum.power));
    out.axis = to_float4(axis, sum.cos_e);
    out.flags = sum.two_sided ? LIGHT_TREE_TWO_SIDED : 0u;
    if (end - start == 1) {
      const Item& it = items_[start];
      const float cos_o = cone ? cone_cos_about(axis, it) : -1.0f;
      out.bounds_max = to_float4(sum.hi, cos_o);
      out.sin_o = float(std::sqrt(std::max(0.0, 1.0 - double(cos_o) * double(cos_o))));
      out.flags |= LIGHT_TREE_LEAF;
      out.index = it.light;
      set_trail(tree_, it.light, bits, depth);
      return depth;
    }
    Summary first_sum, second_sum;
    float cos_o = 1.0f;
    const size_t mid = split(start, end, sum, axis, cone, depth, &cos_o, &first_sum, &second_sum);
    out.bounds_max = to_float4(sum.hi, cos_o);
    out.sin_o = float(std::sqrt(std::max(0.0, 1.0 - double(cos_o) * double(cos_o))));
    const uint32_t first = node + 1u, second = node + uint32_t(2 * (mid - start));
    out.index = second;
    const uint64_t second_bits = bits | (uint64_t(1) << depth);
    // The top levels' second subtrees on another thread: each subtree
    // writes only its own nodes, items and trails, so the tree is the same.
    if (depth < 2 && end - start > 4096) {
      auto other = std::async(std::launch::async, [&, second_bits] {
        return build(mid, end, second_sum, second, second_bits, depth + 1);
      });
      const int a = build(start, mid, first_sum, first, bits, depth + 1);
      return std::max(a, other.get());
    }
    const int a = build(start, mid, first_sum, first, bits, depth + 1);
    return std::max(a, build(mid, end, second_sum, second, second_bits, depth + 1));
  }

  // Where items [start, end) split: the cheapest bucket boundary, or half
  // by count where the centroids coincide, no boundary separates them, or
  // the tree is deep (kCountSplitDepth). One pass takes each light's cone
  // about the node's axis (*cos_o: the node's, their least) and bins it on
  // every axis; a second moves the lights to their sides and sums up each
  // side (*first_sum, *second_sum).
  size_t split(size_t start, size_t end, const Summary& sum, const glm::vec3& axis, bool cone, int depth,
               float* cos_o, Summary* first_sum, Summary* second_sum) {
    const size_t half = start + (end - start) / 2;
    const glm::vec3 extent = sum.hi - sum.lo, centroid_extent = sum.centroid_hi - sum.centroid_lo;
    const float longest = std::max({extent.x, extent.y, extent.z});
    const bool by_count = depth >= kCountSplitDepth;
    Union bucket_sets[3][kBuckets];
    bool split_dim[3];
    float scales[3];
    for (int dim = 0; dim < 3; ++dim) {
      split_dim[dim] = !by_count && centroid_extent[dim] > 0.0f;
      scales[dim] = split_dim[dim] ? kBuckets / centroid_extent[dim] : 0.0f;
    }
    if (end - start == 2 && !by_count) return split_pair(start, sum, axis, cone, cos_o, first_sum, second_sum);
    float least = 1.0f;
    for (size_t i = start; i < end; ++i) {
      const Item& it = items_[i];
      const float c = cone_cos_about(axis, it);  // the buckets' cones too where the node's is whole
      least = std::min(least, c);
      for (int dim = 0; dim < 3; ++dim)
        if (split_dim[dim]) bucket_sets[dim][bucket_of(it.centroid[dim], sum.centroid_lo[dim], scales[dim])].add(it, c);
    }
    *cos_o = cone ? least : -1.0f;
    double best_cost = std::numeric_limits<double>::infinity();
    int best_dim = -1, best_bucket = -1;
    for (int dim = 0; dim < 3; ++dim) {
      if (!split_dim[dim]) continue;
      const Union* buckets = bucket_sets[dim];
      const double aspect = extent[dim] > 0.0f ? longest / extent[dim] : 1.0;
      // The cost of the lights above each boundary, from the top down.
      double above_cost[kBuckets];
      int above_count[kBuckets];
      Union above;
      for (int b = kBuckets - 1; b > 0; --b) {
        above.add(buckets[b]);
        above_count[b] = above.count;
        // Only boundaries after a nonempty bucket are weighed (below).
        above_cost[b] = above.count > 0 && buckets[b - 1].count > 0 ? above.cost(aspect) : 0.0;
      }
      Union below;
      for (int b = 0; b + 1 < kBuckets; ++b) {
        below.add(buckets[b]);
        // An empty bucket repeats the split before it.
        if (buckets[b].count == 0 || below.count == 0 || above_count[b + 1] == 0) continue;
        const double cost = below.cost(aspect) + above_cost[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_dim = dim;
          best_bucket = b;
        }
      }
    }
    if (best_dim < 0) {
      for (size_t i = start; i < half; ++i) first_sum->add(items_[i]);
      for (size_t i = half; i < end; ++i) second_sum->add(items_[i]);
      return half;
    }
    const float scale = scales[best_dim];
    const float origin = sum.centroid_lo[best_dim];
    // A stable partition through the scratch copy (std::stable_partition
    // would allocate a buffer at every node); both sides are nonempty (the
    // chosen boundary has lights on either side).
    size_t mid = start, back = end;
    for (size_t i = start; i < end; ++i) {
      const Item& it = items_[i];
      if (bucket_of(it.centroid[best_dim], origin, scale) <= best_bucket) {
        first_sum->add(it);
        items_[mid++] = it;
      } else {
        second_sum->add(it);
        scratch_[--back] = it;
      }
    }
    std::reverse_copy(scratch_.begin() + std::ptrdiff_t(back), scratch_.begin() + std::ptrdiff_t(end),
                      items_.begin() + std::ptrdiff_t(mid));
    return mid;
  }

  // split() for two lights (half the nodes with children), without the
  // buckets, to the same result: every boundary between them costs the two
  // lights alike but for the aspect, so the split is along the longest
  // axis of the node's box (the first of equals) on which their centroids
  // differ, the lower centroid first; halves where they coincide.
  size_t split_pair(size_t start, const Summary& sum, const glm::vec3& axis, bool cone, float* cos_o,
                    Summary* first_sum, Summary* second_sum) {
    const float least = std::min(cone_cos_about(axis, items_[start]), cone_cos_about(axis, items_[start + 1]));
    *cos_o = cone ? least : -1.0f;
    const glm::vec3 extent = sum.hi - sum.lo;
    int best_dim = -1;
    for (int dim = 0; dim < 3; ++dim)
      if (sum.centroid_hi[dim] - sum.centroid_lo[dim] > 0.0f && (best_dim < 0 || extent[dim] > extent[best_dim]))
        best_dim = dim;
    if (best_dim >= 0 && items_[start + 1].centroid[best_dim] < items_[start].centroid[best_dim])
      std::swap(items_[start], items_[start + 1]);
    first_sum->add(items_[start]);
    second_sum->add(items_[start + 1]);
    return start + 1;
  }

  static int bucket_of(float x, float origin, float scale) {
    return std::clamp(int((x - origin) * scale), 0, kBuckets - 1);
  }

  std::vector<Item>& items_;
  LightTree& tree_;
  std::vector<Item> scratch_;  // per item position: the partition's second side, reversed
};


// A balanced subtree over `entries` (light, weight) at `node`, every
// interior node picking by weight (LIGHT_TREE_BY_POWER); its trails start
// with (bits, depth).
void build_by_weight(const std::vector<std::pair<uint32_t, float>>& entries, size_t start, size_t end, uint32_t node,
                     uint64_t bits, int depth, LightTree& tree) {
  LightTreeNode& out = tree.nodes[node];
  out = LightTreeNode{};
  double weight = 0.0;
  for (size_t i = start; i < end; ++i) weight += entries[i].second;
  out.bounds_min.w = float(weight);
  tree.max_depth = std::max(tree.max_depth, depth);
  if (end - start == 1) {
    out.flags = LIGHT_TREE_LEAF;
    out.index = entries[start].first;
    set_trail(tree, entries[start].first, bits, depth);
    return;
  }
  const size_t mid = start + (end - start) / 2;
  out.flags = LIGHT_TREE_BY_POWER;
  out.index = node + uint32_t(2 * (mid - start));
  build_by_weight(entries, start, mid, node + 1u, bits, depth + 1, tree);
  build_by_weight(entries, mid, end, out.index, bits | (uint64_t(1) << depth), depth + 1, tree);
}

std::vector<Item> positioned_items(const std::vector<Light>& lights, const std::vector<float>& power) {
  std::vector<Item> items;
  items.reserve(lights.size());
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const LightType& type = light_type(lights[i].kind);
    if (!type.tree_bounds || !(i < power.size() && power[i] > 0.0f)) continue;
    Item item;
    item.bounds = type.tree_bounds(lights[i]);
    item.centroid = 0.5f * (item.bounds.lo + item.bounds.hi);
    item.power = power[i];
    item.sin_o = std::sqrt(std::max(0.0f, 1.0f - item.bounds.cos_o * item.bounds.cos_o));
    item.light = i;
    items.push_back(item);
  }
  return items;
}

}  // namespace

LightSampler parse_light_sampler(const std::string& name) {
  if (name == "auto") return LightSampler::Auto;
  if (name == "tree") return LightSampler::Tree;
  if (name == "power") return LightSampler::Power;
  if (name == "uniform") return LightSampler::Uniform;
  throw Error("--light-sampler " + name + ": expected auto, tree, power or uniform");
}

const char* light_sampler_name(LightSampler sampler) {
  switch (sampler) {
    case LightSampler::Auto: return "auto";
    case LightSampler::Tree: return "tree";
    case LightSampler::Power: return "power";
    case LightSampler::Uniform: return "uniform";
  }
  return "unknown";
}

LightTree build_light_tree(const std::vector<Light>& lights, const std::vector<float>& power) {
  const auto t0 = std::chrono::steady_clock::now();
  LightTree tree;
  tree.trails.assign(lights.size(), LightTreeTrail{});
  std::vector<Item> items = positioned_items(lights, power);
  if (!items.empty()) {
    tree.nodes.resize(2 * items.size() - 1);
    Builder builder(items, tree);
    tree.max_depth = builder.build_root(0u, 0u, 0);
    for (const Item& it : items) tree.lights.push_back(it.light);
  }
  tree.build_ms = ms_since(t0);
  return tree;
}

LightTree build_sampling_tree(const std::vector<Light>& lights, const std::vector<float>& power, LightSampler sampler) {
  const auto t0 = std::chrono::steady_clock::now();
  LightTree tree;
  tree.trails.assign(lights.size(), LightTreeTrail{});
  if (sampler == LightSampler::Uniform) {
    std::vector<std::pair<uint32_t, float>> all;
    for (uint32_t i = 0; i < lights.size(); ++i)
      if (i < power.size() && power[i] > 0.0f) all.emplace_back(i, 1.0f);
    if (!all.empty()) {
      tree.nodes.resize(2 * all.size() - 1);
      build_by_weight(all, 0, all.size(), 0u, 0u, 0, tree);
      for (const auto& e : all) tree.lights.push_back(e.first);
    }
    tree.build_ms = ms_since(t0);
    return tree;
  }
  std::vector<Item> items = positioned_items(lights, power);
  std::vector<std::pair<uint32_t, float>> distant;
  for (uint32_t i = 0; i < lights.size(); ++i)
    if (!light_type(lights[i].kind).tree_bounds && i < power.size() && power[i] > 0.0f)
      distant.emplace_back(i, power[i]);
  const size_t count = items.size() + distant.size();
  if (count == 0) return tree;
  tree.nodes.resize(2 * count - 1);
  if (distant.empty() || items.empty()) {
    if (!items.empty()) {
      Builder builder(items, tree);
      tree.max_depth = builder.build_root(0u, 0u, 0);
    } else {
      build_by_weight(distant, 0, distant.size(), 0u, 0u, 0, tree);
    }
  } else {
    // The root: the lights at infinity (first) or the positioned lights'
    // tree (second), by power.
    double local_power = 0.0, distant_power = 0.0;
    for (const Item& it : items) local_power += it.power;
    for (const auto& d : distant) distant_power += d.second;
    LightTreeNode& root = tree.nodes[0];
    root = LightTreeNode{};
    root.flags = LIGHT_TREE_BY_POWER;
    root.bounds_min.w = float(local_power + distant_power);
    root.index = uint32_t(2 * distant.size());
    build_by_weight(distant, 0, distant.size(), 1u, 0u, 1, tree);
    Builder builder(items, tree);
    tree.max_depth = std::max(tree.max_depth, builder.build_root(root.index, 1u, 1));
  }
  for (const auto& d : distant) tree.lights.push_back(d.first);
  for (const Item& it : items) tree.lights.push_back(it.light);
  tree.build_ms = ms_since(t0);
  return tree;
}

}  // namespace caustica
