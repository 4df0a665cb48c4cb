// The wide BVH collapsed from the binary one (host/accel/bvh_wide.h): the
// invariants the traversal relies on (kernels/lib/bvh_traverse.h), checked
// on the host. Traversal against brute force is in test_bvh.cpp.
#include <cstring>
#include <gtest/gtest.h>

#include <algorithm>
#include <glm/glm.hpp>
#include <random>
#include <set>

#include "host/accel/bvh_wide.h"

namespace caustica {
namespace {

using glm::vec3;

struct Rng {
  std::mt19937 gen;
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  vec3 in_box(float h) { return vec3(uniform(-h, h), uniform(-h, h), uniform(-h, h)); }
  vec3 unit() {
    std::normal_distribution<float> g;
    return glm::normalize(vec3(g(gen), g(gen), g(gen)));
  }
};

Scene random_scene(uint32_t seed, int spheres, int cylinders, int triangles) {
  Scene s;
  Rng rng{std::mt19937(seed)};
  for (int i = 0; i < spheres; ++i)
    s.spheres.push_back(Sphere{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.6f)), 0, 0, 0, 0});
  for (int i = 0; i < cylinders; ++i)
    s.cylinders.push_back(Cylinder{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.4f)),
                                   to_float4(rng.unit(), rng.uniform(0.1f, 1.2f)), 0, 0, 0, 0});
  for (int i = 0; i < triangles; ++i) {
    const vec3 c = rng.in_box(10);
    const float size = rng.uniform(0.1f, 3.0f);  // some long enough for spatial splits
    s.triangles.push_back(Triangle{to_float4(c + size * rng.unit()), to_float4(c + size * rng.unit()),
                                   to_float4(c + size * rng.unit()), 0, 0, 0, 0});
  }
  return s;
}

struct Box {
  vec3 lo, hi;
};

Box slot_box(const BvhNode8& n, int i) {
  return {vec3(n.lo_x[i], n.lo_y[i], n.lo_z[i]), vec3(n.hi_x[i], n.hi_y[i], n.hi_z[i])};
}
bool inside(const Box& c, const Box& p) {
  return glm::all(glm::greaterThanEqual(c.lo, p.lo)) && glm::all(glm::lessThanEqual(c.hi, p.hi));
}
bool overlaps(const Box& a, const Box& b) {
  return glm::all(glm::lessThanEqual(a.lo, b.hi)) && glm::all(glm::lessThanEqual(b.lo, a.hi));
}
Box triangle_box(const Triangle& t) {
  const vec3 a = to_vec3(t.v0), b = to_vec3(t.v1), c = to_vec3(t.v2);
  return {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
}

// Walks the tree from the root: each inner node reached exactly once, boxes
// nested, heights right, leaves in range and typed, padding lanes inert;
// returns every primitive reference the leaves hold.
double half_area(const Box& b) {
  const glm::dvec3 e = glm::max(glm::dvec3(b.hi) - glm::dvec3(b.lo), glm::dvec3(0.0));
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

std::set<uint32_t> check_wide(const Scene& s, const WideBvh& w, double* sah = nullptr) {
  std::set<uint32_t> refs;
  double node_area = 0.0, leaf_area = 0.0, root_area = 0.0;
  std::vector<int> seen(w.nodes.size(), 0);
  struct Item {
    uint32_t node;
    Box box;
  };
  const float big = 1e30f;
  vec3 root_lo(big), root_hi(-big);
  std::vector<Item> todo = {{0, {vec3(-big), vec3(big)}}};
  std::vector<uint32_t> order;  // preorder, to check heights bottom-up afterwards
  while (!todo.empty()) {
    const Item it = todo.back();
    todo.pop_back();
    EXPECT_LT(it.node, w.nodes.size());
    if (it.node >= w.nodes.size() || seen[it.node]++) {
      ADD_FAILURE() << "node " << it.node << " reached twice or out of range";
      continue;
    }
    order.push_back(it.node);
    const BvhNode8& n = w.nodes[it.node];
    for (int i = 0; i < WIDE_WIDTH; ++i) {
      const uint32_t c = n.child[i];
      const Box b = slot_box(n, i);
      if (c == WIDE_CHILD_EMPTY) {
        EXPECT_EQ(n.lo_x[i], 1e18f);
        EXPECT_EQ(n.hi_z[i], -1e18f);
        continue;
      }
      EXPECT_TRUE(inside(b, it.box)) << "node " << it.node << " slot " << i << " sticks out of its parent";
      if (it.node == 0) {
        root_lo = glm::min(b.lo, root_lo);
        root_hi = glm::max(b.hi, root_hi);
      }
      if (!(c & WIDE_LEAF_FLAG)) {
        node_area += half_area(b);
        EXPECT_LT(c, WIDE_NODE_INDEX_MASK + 1u);
        todo.push_back({c, b});
        continue;
      }
      const uint32_t first = c & WIDE_LEAF_INDEX_MASK, count = ((c >> WIDE_LEAF_COUNT_SHIFT) & 7u) + 1u;
      leaf_area += half_area(b) * count;
      if (c & WIDE_LEAF_PRIMS) {
        EXPECT_LE(first + count, w.prim_refs.size());
        for (uint32_t k = first; k < first + count && k < w.prim_refs.size(); ++k) {
          EXPECT_NE(w.prim_refs[k] >> PRIM_TYPE_SHIFT, PRIM_TRIANGLE);
          refs.insert(w.prim_refs[k]);
        }
        continue;
      }
      EXPECT_LE(first + count, w.triangle_blocks.size());
      for (uint32_t k = first; k < first + count && k < w.triangle_blocks.size(); ++k) {
        const TriangleBlock4& block = w.triangle_blocks[k];
        for (int lane = 0; lane < 4; ++lane) {
          const uint32_t ref = block.ref[lane];
          EXPECT_EQ(ref >> PRIM_TYPE_SHIFT, PRIM_TRIANGLE);
          if ((ref >> PRIM_TYPE_SHIFT) != PRIM_TRIANGLE || (ref & PRIM_INDEX_MASK) >= s.triangles.size()) continue;
          const Triangle& t = s.triangles[ref & PRIM_INDEX_MASK];
          EXPECT_EQ(block.v[0][lane], t.v0.x);
          EXPECT_EQ(block.v[4][lane], t.v1.y);
          EXPECT_EQ(block.v[8][lane], t.v2.z);
          // A spatial split may clip the box to part of the triangle, never off it.
          EXPECT_TRUE(overlaps(triangle_box(t), b)) << "triangle " << (ref & PRIM_INDEX_MASK);
          refs.insert(ref);
        }
      }
    }
  }
  for (size_t i = order.size(); i-- > 0;) {
    const BvhNode8& n = w.nodes[order[i]];
    uint32_t height = 1;
    for (uint32_t c : n.child)
      if (c != WIDE_CHILD_EMPTY && !(c & WIDE_LEAF_FLAG)) height = std::max(height, w.nodes[c].height + 1);
    EXPECT_EQ(n.height, height) << "node " << order[i];
  }
  EXPECT_EQ(order.size(), w.nodes.size()) << "unreachable nodes";
  EXPECT_EQ(w.height, static_cast<int>(w.nodes[0].height));
  EXPECT_LT(w.height, kWideStackSize);
  // The statistics bench prints: every node but the root at its slot's
  // area, the root at the union of its slots, leaves times their blocks.
  if (!w.nodes.empty() && root_lo.x <= root_hi.x) root_area = half_area(Box{root_lo, root_hi});
  if (root_area > 0.0) {
    EXPECT_NEAR(w.node_sah, (node_area + root_area) / root_area, 1e-3 * w.node_sah);
    EXPECT_NEAR(w.leaf_sah, leaf_area / root_area, 1e-3 * w.leaf_sah + 1e-9);
    if (sah) *sah = w.node_sah + w.leaf_sah;
  }
  return refs;
}

void expect_every_primitive(const Scene& s, const std::set<uint32_t>& refs) {
  EXPECT_EQ(refs.size(), s.primitive_count());
  for (size_t i = 0; i < s.triangles.size(); ++i)
    EXPECT_TRUE(refs.count(PRIM_TRIANGLE << PRIM_TYPE_SHIFT | uint32_t(i))) << "triangle " << i;
  for (size_t i = 0; i < s.spheres.size(); ++i)
    EXPECT_TRUE(refs.count(PRIM_SPHERE << PRIM_TYPE_SHIFT | uint32_t(i))) << "sphere " << i;
  for (size_t i = 0; i < s.cylinders.size(); ++i)
    EXPECT_TRUE(refs.count(PRIM_CYLINDER << PRIM_TYPE_SHIFT | uint32_t(i))) << "cylinder " << i;
}

using Collapse = WideBvhOptions::Collapse;

class EveryCollapse : public testing::TestWithParam<Collapse> {
 protected:
  WideBvhOptions options() const {
    WideBvhOptions o;
    o.collapse = GetParam();
    return o;
  }
};

INSTANTIATE_TEST_SUITE_P(WideBvh, EveryCollapse, testing::Values(Collapse::Sah, Collapse::Greedy),
                         [](const testing::TestParamInfo<Collapse>& i) {
                           return std::string(i.param == Collapse::Sah ? "Sah" : "Greedy");
                         });

TEST_P(EveryCollapse, EveryBuildQualityCollapsesToAValidTree) {
  const Scene s = random_scene(3, 1500, 1500, 4000);
  for (auto quality : {BvhBuildOptions::Quality::Fast, BvhBuildOptions::Quality::Sah,
                       BvhBuildOptions::Quality::Spatial}) {
    BvhBuildOptions options;
    options.quality = quality;
    const Bvh binary = build_bvh(s, options);
    const WideBvh w = collapse_bvh(binary, s, this->options());
    SCOPED_TRACE("quality " + std::to_string(static_cast<int>(quality)));
    expect_every_primitive(s, check_wide(s, w));
    EXPECT_LT(w.nodes.size(), binary.nodes.size() / 3);  // wide: far fewer nodes than the binary tree
    EXPECT_LE(w.height, binary.max_depth + 1);
    // A mesh-like scene: merged subtrees keep the 4-wide blocks mostly full.
    const Scene mesh = random_scene(6, 0, 0, 4000);
    const WideBvh m = collapse_bvh(build_bvh(mesh, options), mesh, this->options());
    expect_every_primitive(mesh, check_wide(mesh, m));
    EXPECT_GT(m.triangle_lanes, 5 * m.triangle_blocks.size() / 2);
  }
}

// Depth-limited builds make leaves of hundreds of primitives: they become
// several chunks (blocks of triangles, runs of other refs), grouped under
// wide nodes of their own when a slot cannot hold them.
TEST_P(EveryCollapse, HugeLeavesBecomeChunks) {
  const Scene s = random_scene(4, 400, 400, 2000);
  BvhBuildOptions options;
  options.max_depth = 2;
  const Bvh binary = build_bvh(s, options);
  ASSERT_LE(binary.max_depth, 2);
  const WideBvh w = collapse_bvh(binary, s, this->options());
  expect_every_primitive(s, check_wide(s, w));
  EXPECT_GT(w.nodes.size(), 1u);
}

TEST_P(EveryCollapse, SinglePrimitiveAndEmptyScene) {
  Scene one;
  one.spheres.push_back(Sphere{to_float4(vec3(1, 2, 3), 0.5f), 0, 0, 0, 0});
  const WideBvh w = collapse_bvh(build_bvh(one), one, options());
  ASSERT_EQ(w.nodes.size(), 1u);
  EXPECT_EQ(w.nodes[0].child[0], WIDE_LEAF_FLAG | WIDE_LEAF_PRIMS);  // one ref at 0
  for (int i = 1; i < WIDE_WIDTH; ++i) EXPECT_EQ(w.nodes[0].child[i], WIDE_CHILD_EMPTY);
  expect_every_primitive(one, check_wide(one, w));

  const Scene none;
  const WideBvh empty = collapse_bvh(build_bvh(none), none, options());
  ASSERT_EQ(empty.nodes.size(), 1u);
  for (uint32_t c : empty.nodes[0].child) EXPECT_EQ(c, WIDE_CHILD_EMPTY);
  EXPECT_TRUE(empty.triangle_blocks.empty());
}

// The dynamic program minimises the SAH over every way of cutting the
// binary tree into wide nodes and leaves, the greedy rule's cuts included:
// it never does worse by that measure, and it packs small subtrees into
// multi-block leaves, so it makes fewer nodes.
TEST(WideBvh, CostDrivenCollapseBeatsGreedyOnSah) {
  for (uint32_t seed : {7u, 8u}) {
    const Scene mixed = random_scene(seed, 300, 300, 3000);
    const Scene mesh = random_scene(seed + 10, 0, 0, 6000);
    for (const Scene* s : {&mixed, &mesh}) {
      BvhBuildOptions build;
      build.quality = BvhBuildOptions::Quality::Spatial;
      const Bvh binary = build_bvh(*s, build);
      WideBvhOptions greedy_options;
      greedy_options.collapse = Collapse::Greedy;
      const WideBvh dp = collapse_bvh(binary, *s);
      const WideBvh greedy = collapse_bvh(binary, *s, greedy_options);
      double dp_sah = 0.0, greedy_sah = 0.0;
      expect_every_primitive(*s, check_wide(*s, dp, &dp_sah));
      expect_every_primitive(*s, check_wide(*s, greedy, &greedy_sah));
      SCOPED_TRACE(s == &mesh ? "mesh" : "mixed");
      EXPECT_LE(dp_sah, greedy_sah * 1.0001);
      EXPECT_LT(dp.nodes.size(), greedy.nodes.size());
      EXPECT_LT(dp.leaves, dp.triangle_blocks.size() + dp.prim_refs.size());  // some leaves hold several blocks
    }
  }
}

// The triangle blocks are written by several threads (WideBvhOptions::threads):
// the tree must be the same byte for byte whatever their number. Large
// enough that the block fill is split between threads.
TEST(WideBvh, IdenticalForAnyThreadCount) {
  const Scene s = random_scene(5, 200, 200, 60000);
  BvhBuildOptions build;
  build.quality = BvhBuildOptions::Quality::Spatial;
  const Bvh binary = build_bvh(s, build);
  WideBvhOptions one_thread;
  one_thread.threads = 1;
  const WideBvh one = collapse_bvh(binary, s, one_thread);
  expect_every_primitive(s, check_wide(s, one, nullptr));
  for (int threads : {2, 3, 0}) {
    WideBvhOptions options;
    options.threads = threads;
    const WideBvh w = collapse_bvh(binary, s, options);
    SCOPED_TRACE(threads);
    ASSERT_EQ(w.nodes.size(), one.nodes.size());
    ASSERT_EQ(w.triangle_blocks.size(), one.triangle_blocks.size());
    EXPECT_EQ(std::memcmp(w.nodes.data(), one.nodes.data(), one.nodes.size() * sizeof(BvhNode8)), 0);
    EXPECT_EQ(std::memcmp(w.triangle_blocks.data(), one.triangle_blocks.data(),
                          one.triangle_blocks.size() * sizeof(TriangleBlock4)),
              0);
    EXPECT_EQ(w.prim_refs, one.prim_refs);
  }
}

}  // namespace
}  // namespace caustica
