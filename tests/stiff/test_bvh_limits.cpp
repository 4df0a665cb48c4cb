// BVH limits (issue 14): inputs that defeat every split rule, through the
// build the renderer uses (spatial splits, then the wide collapse) and the
// real device traversal (intersect_closest).
//   1. N triangles sharing one centroid (all their boxes centred at the
//      origin, random shapes and orientations): no object split separates
//      them, so the builder falls back to median halving.
//   2. N identical triangles: no split of any kind separates them, and a ray
//      through the triangle meets all N (closest hit visits every leaf).
// Each must build within the depth bound (binary depth <= kBvhMaxDepth, wide
// height < CS_BVH_STACK_SIZE, which is what keeps the traversal stack from
// overflowing: kernels/lib/bvh_traverse.h) and trace a few thousand rays to
// the right answers: brute force on a sample, exact distances for the
// identical ones.
//
// Sizes: each case runs twice. With the renderer's default build (spatial
// splits) at N = 10^5: at 10^6 that build alone takes 35 s (one centroid)
// and 15 s (identical) on two shared cores, over the suite's budget. And at
// N = 10^6 with the fast build (--bvh fast, the one for huge scenes), which
// builds either in about half a second. The rays are cut where they cost N
// triangle tests each: a ray that enters the box of N identical triangles
// tests all of them (every leaf has that box), so 64 rays do (32 through
// the triangle, 32 beside it inside its box) and the rest pass outside the
// box; through the fast tree of the one-centroid case a ray costs ~6 ms, so
// it gets 512 rays there and 4096 with spatial splits. Measured: ~8 s for
// all four on two shared cores.
// Found: both finish, every answer right. Spatial splits at one centroid go
// deepest: binary depth 44 at 10^5 and 51 at 10^6 (the builder stops SAH
// and spatial splits where only median halving still fits under the bound
// of 64), wide height 20 and 28; the fast build stays at depth 17.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <random>

#include "host/bench/host_trace.h"
#include "tests/stiff/stiff_support.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::vec3;

struct Limits {
  const char* name;
  BvhBuildOptions::Quality quality;
  size_t count;
  int centroid_rays;  // rays at the one-centroid cluster
};

class BvhLimits : public ::testing::TestWithParam<Limits> {};

Triangle tri(vec3 a, vec3 b, vec3 c) { return Triangle{to_float4(a), to_float4(b), to_float4(c), 0, 0, 0, 0}; }

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The depth bounds, and the measure line.
void expect_within_bounds(const stiff::DeviceTracer& tracer, const char* what, size_t count, double build_ms) {
  const Limits& p = BvhLimits::GetParam();
  std::printf("[measure] %s, %s build: %zu triangles, built (binary + wide) in %.0f ms, binary depth %d, wide height "
              "%d, %zu wide nodes\n",
              what, p.name, count, build_ms, tracer.bvh().max_depth, tracer.wide().height,
              tracer.wide().nodes.size());
  EXPECT_LE(tracer.bvh().max_depth, kBvhMaxDepth) << what;
  EXPECT_LT(tracer.wide().height, CS_BVH_STACK_SIZE) << what;
}

TEST_P(BvhLimits, TrianglesSharingOneCentroid) {
  const Limits& p = GetParam();
  // On Oclgrind a ray through the one-centroid cluster costs seconds at
  // these N (~6 ms on PoCL): N / 100 and 16 rays there (the brute-force
  // sample), still deep median-split trees for its memory checks.
  const size_t kCount = test::sized(p.count, p.count / 100);
  Scene s;
  s.materials.resize(1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> size(0.1f, 1.0f), sign(-1.0f, 1.0f);
  s.triangles.reserve(kCount);
  for (size_t i = 0; i < kCount; ++i) {
    // v1 = -v0 and v2 inside their box: every component's range is
    // symmetric, so every box's centre is exactly the origin.
    const vec3 a(size(rng) * (sign(rng) < 0 ? -1.0f : 1.0f), size(rng), size(rng));
    const vec3 c(a.x, -a.y, a.z * sign(rng));
    s.triangles.push_back(tri(a, -a, c));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const stiff::DeviceTracer tracer(s, p.quality);
  expect_within_bounds(tracer, "one centroid", kCount, ms_since(t0));

  // Rays from a sphere of radius 5 at random points of the cluster's box.
  std::vector<vec3> o, d;
  std::normal_distribution<float> g;
  for (size_t i = 0; i < test::sized(size_t(p.centroid_rays), 16); ++i) {
    const vec3 from = 5.0f * glm::normalize(vec3(g(rng), g(rng), g(rng)));
    const vec3 to(sign(rng), sign(rng), sign(rng));
    o.push_back(from);
    d.push_back(glm::normalize(to - from));
  }
  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<Hit> hits = tracer.closest(o, d);
  const double trace_ms = ms_since(t1);
  size_t hit_count = 0;
  for (const Hit& h : hits) hit_count += h.prim != PRIM_NONE;
  std::printf("[measure] one centroid, %s build: %zu rays in %.0f ms, %zu hits\n", p.name, o.size(), trace_ms,
              hit_count);
  EXPECT_GT(hit_count, o.size() / 2);

  // Brute force on a sample: the same nearest distance.
  for (size_t i = 0; i < 16; ++i) {
    float best = RAY_T_FAR;
    for (const Triangle& t : s.triangles) {
      float tt = best, u = 0.0f, v = 0.0f;
      if (host_intersect_triangle(to_vec3(t.v0), to_vec3(t.v1), to_vec3(t.v2), o[i], d[i], 0.0f, &tt, &u, &v))
        best = tt;
    }
    if (best == RAY_T_FAR) {
      EXPECT_EQ(hits[i].prim, PRIM_NONE) << i;
    } else {
      ASSERT_NE(hits[i].prim, PRIM_NONE) << i;
      EXPECT_EQ(hits[i].t, best) << i;
    }
  }
}

TEST_P(BvhLimits, IdenticalTriangles) {
  const Limits& p = GetParam();
  // Each ray into the box tests all N copies: N / 100, and 4 rays through
  // the triangle, 4 beside it and 64 in all, on Oclgrind.
  const size_t kCount = test::sized(p.count, p.count / 100), kEach = test::sized(32, 4);
  Scene s;
  s.materials.resize(1);
  const vec3 a(-1.0f, -1.0f, 0.0f), b(1.0f, -1.0f, 0.0f), c(0.0f, 1.0f, 0.0f);  // in the plane z = 0
  s.triangles.assign(kCount, tri(a, b, c));
  const auto t0 = std::chrono::steady_clock::now();
  const stiff::DeviceTracer tracer(s, p.quality);
  expect_within_bounds(tracer, "identical", kCount, ms_since(t0));

  // Rays along +z from z = -3: 32 through the triangle (they meet all N
  // copies at t = 3), 32 beside it within its box [-1, 1]^2 (they enter
  // every leaf and meet nothing), the rest outside the box.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f), far(1.5f, 4.0f);
  auto edge_distance = [](vec3 q) {
    return std::fmin(std::fabs(q.y + 1.0f), std::fabs(q.y - (1.0f - 2.0f * std::fabs(q.x))));
  };
  auto inside = [](vec3 q) { return q.y > -1.0f && q.y < 1.0f - 2.0f * std::fabs(q.x); };
  std::vector<vec3> o, d;
  size_t want_hits = 0, beside = 0;
  while (want_hits < kEach || beside < kEach) {
    const vec3 q(coord(rng), coord(rng), -3.0f);
    if (edge_distance(q) < 1e-3f) continue;
    size_t& n = inside(q) ? want_hits : beside;
    if (n == kEach) continue;
    ++n;
    o.push_back(q);
  }
  while (o.size() < test::sized(4096, 64)) o.push_back(vec3(coord(rng), far(rng) * (coord(rng) < 0.0f ? -1.0f : 1.0f), -3.0f));
  d.assign(o.size(), vec3(0.0f, 0.0f, 1.0f));
  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<Hit> hits = tracer.closest(o, d);
  const double trace_ms = ms_since(t1);
  size_t hit_count = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    const bool expect_hit = inside(o[i]);
    EXPECT_EQ(hits[i].prim != PRIM_NONE, expect_hit) << i;
    if (hits[i].prim != PRIM_NONE) {
      ++hit_count;
      EXPECT_NEAR(hits[i].t, 3.0f, 3e-6f) << i;
    }
  }
  std::printf("[measure] identical, %s build: %zu rays (%zu through the triangle, %zu beside it) in %.0f ms\n", p.name,
              o.size(), want_hits, beside, trace_ms);
  EXPECT_EQ(hit_count, want_hits);
}

INSTANTIATE_TEST_SUITE_P(Builds, BvhLimits,
                         ::testing::Values(Limits{"spatial", BvhBuildOptions::Quality::Spatial, 100000, 4096},
                                           Limits{"fast", BvhBuildOptions::Quality::Fast, 1000000, 512}),
                         [](const ::testing::TestParamInfo<Limits>& info) {
                           return std::string(info.param.name) + "_" + std::to_string(info.param.count);
                         });

}  // namespace
}  // namespace caustica
