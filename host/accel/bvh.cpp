#include "host/accel/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

namespace caustica {
namespace {

constexpr float kEmptyLo = 1e18f;  // finite "empty box" bounds: see bvh_traverse.h
constexpr float kEmptyHi = -1e18f;

struct Box {
  glm::vec3 lo{kEmptyLo};
  glm::vec3 hi{kEmptyHi};

  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // Half the surface area: SAH only needs ratios.
  double half_area() const {
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return 0.0;
    glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// Rounds a double bound outward to float so the stored box still contains
// the exact primitive (the traversal relies on boxes being conservative).
float round_down(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::max()) : f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::max()) : f;
}

Box box_around(const glm::dvec3& center, const glm::dvec3& extent) {
  Box b;
  b.lo = {round_down(center.x - extent.x), round_down(center.y - extent.y), round_down(center.z - extent.z)};
  b.hi = {round_up(center.x + extent.x), round_up(center.y + extent.y), round_up(center.z + extent.z)};
  return b;
}

Box sphere_box(const Sphere& s) {
  double r = s.center_radius.w;
  return box_around(glm::dvec3(to_vec3(s.center_radius)), glm::dvec3(r));
}

// Tight box of a capped cylinder: along world axis i the two cap discs reach
// |a_i| * half from the centre plus the disc's own extent r * sqrt(1 - a_i^2).
Box cylinder_box(const Cylinder& c) {
  glm::dvec3 a = glm::dvec3(to_vec3(c.axis_half));
  double half = c.axis_half.w, r = c.center_radius.w;
  glm::dvec3 e;
  for (int i = 0; i < 3; ++i) e[i] = std::abs(a[i]) * half + r * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i]));
  return box_around(glm::dvec3(to_vec3(c.center_radius)), e);
}

Box triangle_box(const Triangle& t) {
  Box b;
  b.grow(to_vec3(t.v0));
  b.grow(to_vec3(t.v1));
  b.grow(to_vec3(t.v2));
  return b;
}

int ceil_log2(uint32_t n) {
  int k = 0;
  while ((uint64_t{1} << k) < n) ++k;
  return k;
}

class Builder {
 public:
  Builder(const BvhBuildOptions& options, Bvh& out) : opt_(options), out_(out) {
    opt_.max_leaf_size = std::max(1, opt_.max_leaf_size);
    opt_.bins = std::clamp(opt_.bins, 2, 256);
    opt_.max_depth = std::clamp(opt_.max_depth, 0, kBvhMaxDepth);
  }

  void add(const Box& box, uint32_t ref) {
    boxes_.push_back(box);
    centroids_.push_back(0.5f * (box.lo + box.hi));
    refs_.push_back(ref);
  }

  void build() {
    const uint32_t n = static_cast<uint32_t>(refs_.size());
    order_.resize(n);
    for (uint32_t i = 0; i < n; ++i) order_[i] = i;
    out_.nodes.reserve(n > 0 ? 2 * n : 1);
    Box root;
    for (const Box& b : boxes_) root.grow(b);
    root_area_ = root.half_area();
    build_node(0, n, 0);
    out_.prim_refs.resize(n);
    for (uint32_t i = 0; i < n; ++i) out_.prim_refs[i] = refs_[order_[i]];
  }

 private:
  struct Bin {
    Box box;
    uint32_t count = 0;
  };

  double relative_area(const Box& b) const { return root_area_ > 0.0 ? b.half_area() / root_area_ : 1.0; }

  int bin_of(const glm::vec3& c, int axis, float lo, float scale) const {
    const float k = (c[axis] - lo) * scale;  // may exceed int range for tiny extents
    if (!(k < static_cast<float>(opt_.bins - 1))) return opt_.bins - 1;
    return k > 0.0f ? static_cast<int>(k) : 0;
  }

  void build_node(uint32_t begin, uint32_t end, int depth) {
    Box box, cbox;
    for (uint32_t i = begin; i < end; ++i) {
      box.grow(boxes_[order_[i]]);
      cbox.grow(centroids_[order_[i]]);
    }
    const uint32_t index = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.push_back(BvhNode{box.lo.x, box.lo.y, box.lo.z, 0u, box.hi.x, box.hi.y, box.hi.z, 0u});
    out_.max_depth = std::max(out_.max_depth, depth);
    const uint32_t count = end - begin;

    if (count <= static_cast<uint32_t>(opt_.max_leaf_size) || depth >= opt_.max_depth) {
      out_.nodes[index].offset = begin;
      out_.nodes[index].count = count;
      out_.sah_cost += relative_area(box) * count;
      return;
    }
    out_.sah_cost += relative_area(box);

    // Median splits halve the count, so once the levels left barely suffice
    // for them, SAH (which may peel off one primitive per level) must stop.
    uint32_t mid = begin;
    if (ceil_log2(count) < opt_.max_depth - depth) mid = sah_partition(begin, end, cbox);
    if (mid == begin || mid == end) mid = median_partition(begin, end, cbox);

    build_node(begin, mid, depth + 1);
    out_.nodes[index].offset = static_cast<uint32_t>(out_.nodes.size());
    build_node(mid, end, depth + 1);
  }

  // Returns the split position, or begin when no plane separates anything.
  uint32_t sah_partition(uint32_t begin, uint32_t end, const Box& cbox) {
    const int nb = opt_.bins;
    double best_cost = std::numeric_limits<double>::max();
    int best_axis = -1, best_split = 0;
    std::array<float, 3> scale{};
    std::vector<Bin>& bins = bins_;
    std::vector<double>& right_cost = right_cost_;
    bins.resize(nb);
    right_cost.resize(nb);
    for (int axis = 0; axis < 3; ++axis) {
      const float extent = cbox.hi[axis] - cbox.lo[axis];
      if (!(extent > 0.0f)) continue;
      scale[axis] = nb / extent;
      std::fill(bins.begin(), bins.end(), Bin{});
      for (uint32_t i = begin; i < end; ++i) {
        Bin& b = bins[bin_of(centroids_[order_[i]], axis, cbox.lo[axis], scale[axis])];
        b.box.grow(boxes_[order_[i]]);
        ++b.count;
      }
      // Sweep from the right storing area * count of everything right of
      // each plane, then from the left evaluating each plane.
      Box acc;
      uint32_t n = 0;
      for (int k = nb - 1; k > 0; --k) {
        acc.grow(bins[k].box);
        n += bins[k].count;
        right_cost[k] = n > 0 ? acc.half_area() * n : -1.0;
      }
      acc = Box{};
      n = 0;
      for (int k = 1; k < nb; ++k) {
        acc.grow(bins[k - 1].box);
        n += bins[k - 1].count;
        if (n == 0 || right_cost[k] < 0.0) continue;
        const double cost = acc.half_area() * n + right_cost[k];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = k;
        }
      }
    }
    if (best_axis < 0) return begin;
    const float lo = cbox.lo[best_axis], s = scale[best_axis];
    auto it = std::partition(order_.begin() + begin, order_.begin() + end,
                             [&](uint32_t p) { return bin_of(centroids_[p], best_axis, lo, s) < best_split; });
    return static_cast<uint32_t>(it - order_.begin());
  }

  // Object median along the widest centroid axis; any halving will do when
  // all centroids coincide.
  uint32_t median_partition(uint32_t begin, uint32_t end, const Box& cbox) {
    const glm::vec3 e = cbox.hi - cbox.lo;
    const int axis = (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    return mid;
  }

  BvhBuildOptions opt_;
  Bvh& out_;
  std::vector<Box> boxes_;
  std::vector<glm::vec3> centroids_;
  std::vector<uint32_t> refs_;
  std::vector<uint32_t> order_;
  std::vector<Bin> bins_;  // scratch reused by every node
  std::vector<double> right_cost_;
  double root_area_ = 0.0;
};

uint32_t make_ref(uint32_t type, size_t index) {
  return (type << PRIM_TYPE_SHIFT) | (static_cast<uint32_t>(index) & PRIM_INDEX_MASK);
}

}  // namespace

Bvh build_bvh(const Scene& scene, const BvhBuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Bvh bvh;
  if (scene.primitive_count() == 0) {
    bvh.nodes.push_back(BvhNode{kEmptyLo, kEmptyLo, kEmptyLo, 0u, kEmptyHi, kEmptyHi, kEmptyHi, 0u});
  } else {
    Builder builder(options, bvh);
    for (size_t i = 0; i < scene.spheres.size(); ++i)
      builder.add(sphere_box(scene.spheres[i]), make_ref(PRIM_SPHERE, i));
    for (size_t i = 0; i < scene.cylinders.size(); ++i)
      builder.add(cylinder_box(scene.cylinders[i]), make_ref(PRIM_CYLINDER, i));
    for (size_t i = 0; i < scene.triangles.size(); ++i)
      builder.add(triangle_box(scene.triangles[i]), make_ref(PRIM_TRIANGLE, i));
    builder.build();
  }
  bvh.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return bvh;
}

}  // namespace caustica
