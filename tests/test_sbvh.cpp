// Spatial-split BVH (BvhBuildOptions::Quality::Spatial): triangles may be
// referenced from several leaves with clipped boxes. Checked here: the
// kernels' queries over it still equal brute force, every part of every
// triangle stays inside some leaf that references it (and every leaf only
// references primitives it overlaps), the duplication budget and depth
// limit hold, the tree is the same for any thread count, and spatial splits
// pay off where they should (long thin diagonal triangles).
#include <algorithm>
#include <array>
#include <cstring>
#include <glm/glm.hpp>
#include <random>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "host/bench/host_trace.h"
#include "host/scene/load_scene.h"
#include "tests/support/bvh_compare.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::dvec3;
using glm::vec3;
using test::add_cylinders;
using test::add_small_triangles;
using test::add_spheres;
using test::add_triangles;
using test::AimAtPrimitives;
using test::expect_matches_brute_force;
using test::expect_outcomes;
using test::flat_index;
using test::KernelBuild;
using test::walk_binary_bvh;
using test::one_ref_per_primitive;
using test::Outcome;
using test::point_in;
using test::random_rays;
using test::Ray;
using test::Rng;
using test::triangle;
using Quality = BvhBuildOptions::Quality;

// Long thin triangles along near-diagonal directions across the scene: each
// one's box is a large, almost empty cube that inflates every node holding
// it, unless spatial splits chop the triangle into pieces with small boxes.
void add_thin_diagonal_triangles(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i) {
    const vec3 diag(rng.uniform(0, 1) < 0.5f ? -1 : 1, rng.uniform(0, 1) < 0.5f ? -1 : 1, 1);
    const vec3 dir = glm::normalize(diag + 0.15f * rng.unit());
    const vec3 side = glm::normalize(glm::cross(dir, rng.unit()));
    const vec3 c = rng.in_box(5);
    const float len = rng.uniform(10.0f, 25.0f), width = rng.uniform(0.05f, 0.2f);
    s.triangles.push_back(triangle(c - 0.5f * len * dir, c + 0.5f * len * dir,
                                   c + rng.uniform(-0.4f, 0.4f) * len * dir + width * side));
  }
}

std::vector<Outcome> host_compare(const Scene& s, const Bvh& bvh, const std::vector<Ray>& rays) {
  const HostTracer tracer(s, bvh);
  const std::vector<uint32_t> all_refs = one_ref_per_primitive(s);
  std::vector<Outcome> out;
  for (const Ray& r : rays) {
    const Hit h = tracer.closest(r.o, r.d, r.tmin, kRayTFar);
    Hit brute = no_hit();
    for (uint32_t ref : all_refs) tracer.intersect_prim(ref, r.o, r.d, r.tmin, &brute);
    out.push_back({h.t, brute.t, h.prim, brute.prim, tracer.any(r.o, r.d, r.tmin, r.tmax_any)});
  }
  return out;
}

// The kernels traverse the wide BVH collapsed from the binary one, which
// keeps the binary leaves' (clipped) boxes.
void expect_device_matches_brute_force(const Scene& s, const Bvh& bvh, const std::vector<Ray>& rays) {
  expect_matches_brute_force(s, collapse_bvh(bvh, s), rays, {KernelBuild::Plain, KernelBuild::FastRelaxedMath});
}

BvhBuildOptions with(Quality q, int threads = 0) {
  BvhBuildOptions o;
  o.quality = q;
  o.threads = threads;
  return o;
}

Scene triangle_scene() {
  Scene s;
  Rng rng{std::mt19937(31)};
  add_triangles(s, rng, 4000);
  return s;
}
Scene mixed_scene() {
  Scene s;
  Rng rng{std::mt19937(32)};
  add_spheres(s, rng, 1200);
  add_cylinders(s, rng, 1200);
  add_triangles(s, rng, 1200);
  return s;
}
Scene thin_scene() {
  Scene s;
  Rng rng{std::mt19937(33)};
  add_small_triangles(s, rng, 2500);
  add_thin_diagonal_triangles(s, rng, 500);
  return s;
}

// ---- structure ----------------------------------------------------------

struct DBox {
  dvec3 lo{1e300}, hi{-1e300};
  void grow(const dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool contains(const dvec3& p, double tol) const {
    return p.x >= lo.x - tol && p.y >= lo.y - tol && p.z >= lo.z - tol && p.x <= hi.x + tol &&
           p.y <= hi.y + tol && p.z <= hi.z + tol;
  }
};

DBox node_box(const BvhNode& n) { return DBox{dvec3(n.lo_x, n.lo_y, n.lo_z), dvec3(n.hi_x, n.hi_y, n.hi_z)}; }

std::array<dvec3, 3> vertices(const Triangle& t) {
  return {dvec3(to_vec3(t.v0)), dvec3(to_vec3(t.v1)), dvec3(to_vec3(t.v2))};
}

// Whether the triangle meets the box (grown by tol): clip its polygon by the
// six planes and see whether anything is left.
bool triangle_meets_box(const Triangle& t, const DBox& b, double tol) {
  const auto v = vertices(t);
  std::vector<dvec3> poly(v.begin(), v.end()), next;
  for (int axis = 0; axis < 3 && !poly.empty(); ++axis)
    for (int side = 0; side < 2 && !poly.empty(); ++side) {
      const double plane = side ? b.hi[axis] + tol : b.lo[axis] - tol;
      auto inside = [&](const dvec3& p) { return side ? p[axis] <= plane : p[axis] >= plane; };
      next.clear();
      for (size_t i = 0; i < poly.size(); ++i) {
        const dvec3 &a = poly[i], &c = poly[(i + 1) % poly.size()];
        if (inside(a)) next.push_back(a);
        if (inside(a) != inside(c)) next.push_back(a + (plane - a[axis]) / (c[axis] - a[axis]) * (c - a));
      }
      poly.swap(next);
    }
  return !poly.empty();
}

DBox prim_box(const Scene& s, uint32_t ref) {
  const uint32_t type = ref >> PRIM_TYPE_SHIFT, idx = ref & PRIM_INDEX_MASK;
  DBox b;
  if (type == PRIM_TRIANGLE) {
    for (const dvec3& p : vertices(s.triangles[idx])) b.grow(p);
  } else {
    const cs_float4 c = type == PRIM_SPHERE ? s.spheres[idx].center_radius : s.cylinders[idx].center_radius;
    const double reach = c.w + (type == PRIM_CYLINDER ? s.cylinders[idx].axis_half.w : 0.0f);
    b.grow(dvec3(to_vec3(c)) - reach);
    b.grow(dvec3(to_vec3(c)) + reach);
  }
  return b;
}

// Layout and containment as in test_bvh.cpp, and for spatial splits:
// - every primitive is referenced at least once; spheres and cylinders
//   exactly once, whole inside their leaf;
// - a leaf references only triangles that meet its box, and its box lies
//   within the union of its primitives' boxes (clipped boxes never grow);
// - every point of every triangle lies in some leaf that references it
//   (checked on vertices, edge points and random interior points);
// - at most `max_ratio` references per primitive.
void check_structure(const Scene& s, const Bvh& bvh, int max_leaf, double max_ratio) {
  const size_t prims = s.primitive_count();
  std::vector<std::vector<uint32_t>> leaves_of(prims);
  std::vector<int> slot_owner(bvh.prim_refs.size(), 0);
  walk_binary_bvh(bvh, max_leaf, [&](uint32_t node, const BvhNode& n) {
    const DBox box = node_box(n);
    DBox prims_box;
    for (uint32_t i = n.offset; i < n.offset + n.count; ++i) {
      ++slot_owner[i];
      const uint32_t ref = bvh.prim_refs[i], type = ref >> PRIM_TYPE_SHIFT, idx = ref & PRIM_INDEX_MASK;
      const size_t flat = flat_index(s, ref);
      ASSERT_LT(flat, prims);
      leaves_of[flat].push_back(node);
      const DBox pb = prim_box(s, ref);
      prims_box.grow(pb.lo);
      prims_box.grow(pb.hi);
      if (type == PRIM_TRIANGLE)
        EXPECT_TRUE(triangle_meets_box(s.triangles[idx], box, 1e-6)) << "triangle " << idx << " misses its leaf";
      else if (type == PRIM_SPHERE)  // (prim_box is loose for cylinders: test_bvh.cpp checks their rims)
        EXPECT_TRUE(box.contains(pb.lo, 0.0) && box.contains(pb.hi, 0.0)) << "sphere " << idx << " not in its leaf";
    }
    EXPECT_TRUE(prims_box.contains(box.lo, 1e-5) && prims_box.contains(box.hi, 1e-5))
        << "leaf " << node << " larger than its primitives";
  });
  if (testing::Test::HasFatalFailure()) return;
  for (size_t i = 0; i < slot_owner.size(); ++i) ASSERT_EQ(slot_owner[i], 1) << "prim_refs slot " << i;
  EXPECT_EQ(bvh.references, bvh.prim_refs.size());
  EXPECT_LE(double(bvh.references), max_ratio * double(prims) + 1.0);

  Rng rng{std::mt19937(5)};
  for (size_t p = 0; p < prims; ++p) {
    ASSERT_FALSE(leaves_of[p].empty()) << "primitive " << p << " in no leaf";
    if (p < s.spheres.size() + s.cylinders.size()) {
      EXPECT_EQ(leaves_of[p].size(), 1u) << "sphere or cylinder " << p << " duplicated";
      continue;
    }
    const Triangle& t = s.triangles[p - s.spheres.size() - s.cylinders.size()];
    const auto v = vertices(t);
    std::vector<dvec3> points(v.begin(), v.end());
    for (int k = 0; k < 3; ++k) points.push_back(0.5 * (v[k] + v[(k + 1) % 3]));
    for (int k = 0; k < 16; ++k) {
      double a = rng.uniform(0, 1), b = rng.uniform(0, 1);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      points.push_back(v[0] + a * (v[1] - v[0]) + b * (v[2] - v[0]));
    }
    for (const dvec3& q : points) {
      const double tol = 1e-6 * (1.0 + std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}));
      const bool covered = std::any_of(leaves_of[p].begin(), leaves_of[p].end(),
                                       [&](uint32_t leaf) { return node_box(bvh.nodes[leaf]).contains(q, tol); });
      if (!covered) {
        ADD_FAILURE() << "triangle " << p << ": point (" << q.x << ", " << q.y << ", " << q.z
                      << ") outside every leaf referencing it";
        return;
      }
    }
  }
}

bool same_tree(const Bvh& a, const Bvh& b) {
  return a.nodes.size() == b.nodes.size() && a.prim_refs == b.prim_refs &&
         std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)) == 0 &&
         a.sah_cost == b.sah_cost && a.max_depth == b.max_depth && a.references == b.references;
}

// ---- tests --------------------------------------------------------------

struct SceneCase {
  const char* name;
  Scene (*make)();
};

class SbvhTraversal : public ::testing::TestWithParam<SceneCase> {};

TEST_P(SbvhTraversal, MatchesBruteForce) {
  const Scene s = GetParam().make();
  const Bvh bvh = build_bvh(s, with(Quality::Spatial));
  ASSERT_GT(bvh.references, s.primitive_count()) << "no spatial split happened: the test would prove nothing";
  Rng rng{std::mt19937(101)};
  // 64 rays on Oclgrind: the device brute force tests every primitive.
  expect_device_matches_brute_force(s, bvh, random_rays(rng, int(test::sized(12000, 64)), s, AimAtPrimitives::Yes));
}

// The binary tree itself, traced on the host with the kernels' scalar
// arithmetic (host/bench/host_trace.h), apart from the wide collapse.
TEST_P(SbvhTraversal, BinaryTreeMatchesBruteForceOnHost) {
  const Scene s = GetParam().make();
  const Bvh bvh = build_bvh(s, with(Quality::Spatial));
  Rng rng{std::mt19937(104)};
  const std::vector<Ray> rays = random_rays(rng, 12000, s, AimAtPrimitives::Yes);
  expect_outcomes(rays, host_compare(s, bvh, rays));
}

// Every primitive is looked for: one ray at an interior point of each, from
// inside and outside the scene. With duplicated references a primitive can
// be tested several times; the answer must still be its nearest t.
TEST_P(SbvhTraversal, FindsEveryPrimitiveAtItsNearestT) {
  const Scene s = GetParam().make();
  const Bvh bvh = build_bvh(s, with(Quality::Spatial));
  Rng rng{std::mt19937(102)};
  std::vector<Ray> rays;
  // Every 64th primitive on Oclgrind (past 120 s for all): the device brute
  // force tests every primitive per ray.
  const size_t step = test::sized(1, 64);
  for (size_t p = 0; p < s.primitive_count(); p += step) {
    Ray r;
    r.o = p % 2 ? rng.in_box(12) : 30.0f * rng.unit();
    r.d = glm::normalize(point_in(s, p, rng) - r.o);
    r.tmin = 0.0f;
    r.tmax_any = 100.0f;
    rays.push_back(r);
  }
  expect_device_matches_brute_force(s, bvh, rays);
}

TEST_P(SbvhTraversal, StructureAndCoverage) {
  const Scene s = GetParam().make();
  const Bvh bvh = build_bvh(s, with(Quality::Spatial));
  check_structure(s, bvh, 4, 1.3);
  std::printf("%s: %zu primitives, %zu references, %zu nodes, depth %d, SAH %.2f, %.1f ms\n", GetParam().name,
              s.primitive_count(), bvh.references, bvh.nodes.size(), bvh.max_depth, bvh.sah_cost, bvh.build_ms);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SbvhTraversal,
                         ::testing::Values(SceneCase{"Triangles", triangle_scene}, SceneCase{"Mixed", mixed_scene},
                                           SceneCase{"ThinDiagonal", thin_scene}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(SbvhBuild, SpatialSplitsLowerTheSahCostOfThinTriangles) {
  const Scene s = thin_scene();
  const Bvh sah = build_bvh(s, with(Quality::Sah));
  const Bvh spatial = build_bvh(s, with(Quality::Spatial));
  std::printf("thin diagonal triangles: SAH cost %.2f (Sah) vs %.2f (Spatial), %zu references\n", sah.sah_cost,
              spatial.sah_cost, spatial.references);
  EXPECT_LT(spatial.sah_cost, sah.sah_cost);
  EXPECT_LT(spatial.sah_cost, 0.8 * sah.sah_cost);  // not a marginal gain: the case SBVH exists for
}

TEST(SbvhBuild, OtherQualitiesReferenceEachPrimitiveOnce) {
  const Scene s = mixed_scene();
  const Bvh sah = build_bvh(s, with(Quality::Sah));
  check_structure(s, sah, 4, 1.0);
  EXPECT_EQ(sah.references, s.primitive_count());
  const Bvh fast = build_bvh(s, with(Quality::Fast));
  check_structure(s, fast, 8, 1.0);  // Fast doubles the leaf size
  EXPECT_EQ(fast.references, s.primitive_count());
  EXPECT_LT(fast.nodes.size(), sah.nodes.size());
}

// Large enough for the parallel paths (subtree jobs, chunked binning at the
// top): the tree must not depend on how the work was spread.
TEST(SbvhBuild, IdenticalForAnyThreadCount) {
  Scene big;
  Rng rng{std::mt19937(34)};
  add_triangles(big, rng, 30000);
  add_thin_diagonal_triangles(big, rng, 5000);
  add_spheres(big, rng, 3000);
  for (const Scene* s : {&big}) {
    for (Quality q : {Quality::Fast, Quality::Sah, Quality::Spatial}) {
      const Bvh one = build_bvh(*s, with(q, 1));
      for (int threads : {2, 3, 4}) EXPECT_TRUE(same_tree(one, build_bvh(*s, with(q, threads)))) << threads;
      EXPECT_TRUE(same_tree(one, build_bvh(*s, with(q, 0))));
    }
  }
  const Scene thin = thin_scene(), mixed = mixed_scene();
  for (const Scene* s : {&thin, &mixed})
    EXPECT_TRUE(same_tree(build_bvh(*s, with(Quality::Spatial, 1)), build_bvh(*s, with(Quality::Spatial, 2))));
}

// Near the depth limit the builder falls back to median splits and makes no
// more spatial splits (they may not shrink a node); the tree must obey the
// limit and still trace right.
TEST(SbvhBuild, DepthLimit) {
  const Scene s = thin_scene();
  BvhBuildOptions limited = with(Quality::Spatial);
  limited.max_depth = 14;
  const Bvh bvh = build_bvh(s, limited);
  EXPECT_LE(bvh.max_depth, 14);
  EXPECT_GT(bvh.references, s.primitive_count());
  check_structure(s, bvh, 4, 1.3);
  Rng rng{std::mt19937(103)};
  // 32 rays on Oclgrind: the device brute force tests every primitive.
  const std::vector<Ray> rays = random_rays(rng, int(test::sized(4000, 32)), s, AimAtPrimitives::Yes);
  expect_outcomes(rays, host_compare(s, bvh, rays));
  expect_device_matches_brute_force(s, bvh, rays);
}

TEST(SbvhBuild, SmallAndDegenerateScenes) {
  Scene one;
  one.triangles.push_back(triangle(vec3(0), vec3(1, 0, 0), vec3(0, 1, 0)));
  Bvh bvh = build_bvh(one, with(Quality::Spatial));
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.references, 1u);

  Scene same;  // identical triangles: no plane separates anything
  for (int i = 0; i < 500; ++i) same.triangles.push_back(triangle(vec3(0), vec3(1, 1, 1), vec3(0, 1, 0)));
  bvh = build_bvh(same, with(Quality::Spatial));
  check_structure(same, bvh, 4, 1.3);

  Scene flat;  // every triangle in the plane z = 0: boxes without depth
  Rng rng{std::mt19937(35)};
  for (int i = 0; i < 2000; ++i) {
    const vec3 c(rng.uniform(-5, 5), rng.uniform(-5, 5), 0.0f);
    flat.triangles.push_back(triangle(c, c + vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), 0),
                                      c + vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), 0)));
  }
  bvh = build_bvh(flat, with(Quality::Spatial));
  check_structure(flat, bvh, 4, 1.3);

  const Scene empty;
  bvh = build_bvh(empty, with(Quality::Spatial));
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.references, 0u);
  EXPECT_EQ(bvh.nodes[0].lo_x, 1e18f);
}

// The conference room (331k triangles), the largest bench scene: each
// quality keeps its promise on a real mesh. Build times are measured by
// BM_BuildConference (caustica_micro_benchmarks) and `caustica bench`, not
// here; this prints them for the log only.
TEST(SbvhBuild, ConferenceQualities) {
  CAUSTICA_REQUIRE_SHARED(shared);
  Scene s;
  try {
    s = load_scene(test::source_dir() + "/bench/scenes/conference_inside.json");
  } catch (const std::exception& e) {
    GTEST_SKIP() << "conference scene not loadable: " << e.what();
  }
  double sah_cost[3] = {0.0, 0.0, 0.0};
  for (Quality q : {Quality::Fast, Quality::Sah, Quality::Spatial}) {
    const Bvh bvh = build_bvh(s, with(q));
    std::printf("conference, quality %d: %.0f ms, SAH cost %.2f, %zu references (%.3f per triangle), depth %d\n",
                int(q), bvh.build_ms, bvh.sah_cost, bvh.references, double(bvh.references) / s.primitive_count(),
                bvh.max_depth);
    sah_cost[int(q)] = bvh.sah_cost;
    if (q == Quality::Spatial) {
      EXPECT_GT(bvh.references, s.primitive_count());  // spatial splits happened
      EXPECT_LE(double(bvh.references), 1.3 * double(s.primitive_count()) + 1.0);  // within the budget
    } else {
      EXPECT_EQ(bvh.references, s.primitive_count());
    }
    EXPECT_LE(bvh.max_depth, kBvhMaxDepth);
  }
  // Each step up in quality buys a lower SAH cost on this scene.
  EXPECT_LT(sah_cost[int(Quality::Sah)], sah_cost[int(Quality::Fast)]);
  EXPECT_LT(sah_cost[int(Quality::Spatial)], sah_cost[int(Quality::Sah)]);
}

}  // namespace
}  // namespace caustica
