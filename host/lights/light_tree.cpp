#include "host/lights/light_tree.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <utility>

#include "host/error.h"

namespace caustica {
namespace {

constexpr int kBuckets = 12;
constexpr int kCountSplitDepth = 40;  // from here on, halves by count (light_tree.h)
constexpr double kPi = 3.14159265358979323846;

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
// cosines about the node's axis, sidedness.
struct Union {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  float power = 0.0f;  // enough to compare splits by
  float cos_o = 1.0f, cos_e = 1.0f;
  int count = 0;
  void add(const Item& item, float cone_cos) {
    lo = glm::min(lo, item.bounds.lo);
    hi = glm::max(hi, item.bounds.hi);
    power += item.power;
    cos_o = std::min(cos_o, cone_cos);
    cos_e = std::min(cos_e, item.bounds.cos_e);
    ++count;
  }
  void add(const Union& u) {
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

class Builder {
 public:
  Builder(std::vector<Item>& items, LightTree& tree)
      : items_(items), tree_(tree), cone_cos_(items.size()), scratch_(items.size()) {}

  // Builds the subtree of items [start, end) at `node`, whose trail is
  // (bits, depth); returns the deepest level below.
  int build(size_t start, size_t end, uint32_t node, uint64_t bits, int depth) {
    LightTreeNode& out = tree_.nodes[node];
    out = LightTreeNode{};
    // The node's bounds: box, power, sidedness, and the cone about its
    // lights' mean axis.
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    glm::vec3 centroid_lo = lo, centroid_hi = hi, axis_sum(0.0f);
    double power = 0.0;
    float cos_e = 1.0f;
    bool two_sided = false, omni = false;
    for (size_t i = start; i < end; ++i) {
      const Item& it = items_[i];
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
    const float axis_length = glm::length(axis_sum);
    const glm::vec3 axis = axis_length > 1e-6f ? axis_sum / axis_length : glm::vec3(0.0f, 0.0f, 1.0f);
    float cos_o = omni || !(axis_length > 1e-6f) ? -1.0f : 1.0f;
    for (size_t i = start; i < end; ++i) {
      cone_cos_[i] = cone_cos_about(axis, items_[i]);
      cos_o = std::min(cos_o, cone_cos_[i]);
    }
    out.bounds_min = to_float4(lo, float(power));
    out.bounds_max = to_float4(hi, cos_o);
    out.sin_o = float(std::sqrt(std::max(0.0, 1.0 - double(cos_o) * double(cos_o))));
    out.axis = to_float4(axis, cos_e);
    out.flags = two_sided ? LIGHT_TREE_TWO_SIDED : 0u;
    if (end - start == 1) {
      out.flags |= LIGHT_TREE_LEAF;
      out.index = items_[start].light;
      set_trail(tree_, items_[start].light, bits, depth);
      return depth;
    }
    const size_t mid = split(start, end, lo, hi, centroid_lo, centroid_hi, depth);
    const uint32_t first = node + 1u, second = node + uint32_t(2 * (mid - start));
    out.index = second;
    const uint64_t second_bits = bits | (uint64_t(1) << depth);
    // The top levels' second subtrees on another thread: each subtree
    // writes only its own nodes, items and trails, so the tree is the same.
    if (depth < 2 && end - start > 4096) {
      auto other = std::async(std::launch::async,
                              [&, second_bits] { return build(mid, end, second, second_bits, depth + 1); });
      const int a = build(start, mid, first, bits, depth + 1);
      return std::max(a, other.get());
    }
    const int a = build(start, mid, first, bits, depth + 1);
    return std::max(a, build(mid, end, second, second_bits, depth + 1));
  }

 private:
  // Where items [start, end) split: the cheapest bucket boundary, or half
  // by count where the centroids coincide, no boundary separates them, or
  // the tree is deep (kCountSplitDepth).
  size_t split(size_t start, size_t end, const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& centroid_lo,
               const glm::vec3& centroid_hi, int depth) {
    const size_t half = start + (end - start) / 2;
    if (depth >= kCountSplitDepth) return half;
    const glm::vec3 extent = hi - lo, centroid_extent = centroid_hi - centroid_lo;
    const float longest = std::max({extent.x, extent.y, extent.z});
    double best_cost = std::numeric_limits<double>::infinity();
    int best_dim = -1, best_bucket = -1;
    // Every axis's buckets in one pass over the items.
    Union bucket_sets[3][kBuckets];
    bool split_dim[3];
    float scales[3];
    for (int dim = 0; dim < 3; ++dim) {
      split_dim[dim] = centroid_extent[dim] > 0.0f;
      scales[dim] = split_dim[dim] ? kBuckets / centroid_extent[dim] : 0.0f;
    }
    for (size_t i = start; i < end; ++i)
      for (int dim = 0; dim < 3; ++dim)
        if (split_dim[dim])
          bucket_sets[dim][bucket_of(items_[i].centroid[dim], centroid_lo[dim], scales[dim])].add(items_[i],
                                                                                                   cone_cos_[i]);
    for (int dim = 0; dim < 3; ++dim) {
      if (!split_dim[dim]) continue;
      const Union* buckets = bucket_sets[dim];
      Union above[kBuckets];
      for (int b = kBuckets - 1; b > 0; --b) {
        above[b] = buckets[b];
        if (b + 1 < kBuckets) above[b].add(above[b + 1]);
      }
      const double aspect = extent[dim] > 0.0f ? longest / extent[dim] : 1.0;
      Union below;
      for (int b = 0; b + 1 < kBuckets; ++b) {
        below.add(buckets[b]);
        // An empty bucket repeats the split before it.
        if (buckets[b].count == 0 || below.count == 0 || above[b + 1].count == 0) continue;
        const double cost = below.cost(aspect) + above[b + 1].cost(aspect);
        if (cost < best_cost) {
          best_cost = cost;
          best_dim = dim;
          best_bucket = b;
        }
      }
    }
    if (best_dim < 0) return half;
    const float scale = kBuckets / centroid_extent[best_dim];
    const float origin = centroid_lo[best_dim];
    // A stable partition through the scratch copy (std::stable_partition
    // would allocate a buffer at every node).
    size_t mid = start, back = end;
    for (size_t i = start; i < end; ++i) {
      if (bucket_of(items_[i].centroid[best_dim], origin, scale) <= best_bucket) items_[mid++] = items_[i];
      else scratch_[--back] = items_[i];
    }
    if (mid == start || mid == end) {  // cannot happen (both sides counted items); kept whole
      std::reverse(scratch_.begin() + std::ptrdiff_t(back), scratch_.begin() + std::ptrdiff_t(end));
      std::copy(scratch_.begin() + std::ptrdiff_t(back), scratch_.begin() + std::ptrdiff_t(end),
                items_.begin() + std::ptrdiff_t(mid));
      return half;
    }
    std::reverse_copy(scratch_.begin() + std::ptrdiff_t(back), scratch_.begin() + std::ptrdiff_t(end),
                      items_.begin() + std::ptrdiff_t(mid));
    return mid;
  }

  static int bucket_of(float x, float origin, float scale) {
    return std::clamp(int((x - origin) * scale), 0, kBuckets - 1);
  }

  std::vector<Item>& items_;
  LightTree& tree_;
  std::vector<float> cone_cos_;  // per item position: its cone's cosine about its current node's axis
  std::vector<Item> scratch_;    // per item position: the partition's second side, reversed
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

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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
    tree.max_depth = builder.build(0, items.size(), 0u, 0u, 0);
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
      tree.max_depth = builder.build(0, items.size(), 0u, 0u, 0);
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
    tree.max_depth = std::max(tree.max_depth, builder.build(0, items.size(), root.index, 1u, 1));
  }
  for (const auto& d : distant) tree.lights.push_back(d.first);
  for (const Item& it : items) tree.lights.push_back(it.light);
  tree.build_ms = ms_since(t0);
  return tree;
}

}  // namespace caustica
