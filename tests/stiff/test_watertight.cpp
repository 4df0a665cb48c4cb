// Watertightness through the real device traversal (issue 14): the BVH the
// renderer builds and its intersect_closest stage.
//   1. A finely tessellated sphere (radius 100, 256 x 512 lat-long cells,
//      261,120 triangles sharing their vertices exactly) centred at
//      (148376, 1234, -223423), where a float's spacing is 1/64: rays from
//      random points inside in uniform directions never miss: 10^7 rays
//      (Embree's verify allows 0.002% misses; we allow none).
//   2. A grid mesh (64 x 64 cells, two triangles each) at the origin and
//      moved 1e4 away, tilted: rays aimed at its vertices (shared by up to
//      six triangles) and at the midpoints of its edges (shared by two),
//      from random points above and below: each finds exactly one hit at
//      the expected distance (closest hit: never a miss through a crack).
// Found: no misses (the watertight test of Woop et al. with its exact fp64
// fallback, and the traversal's widened far planes, already hold there).
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <algorithm>
#include <random>

#include "tests/stiff/stiff_support.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::dvec3;
using glm::vec3;

Triangle tri(vec3 a, vec3 b, vec3 c) { return Triangle{to_float4(a), to_float4(b), to_float4(c), 0, 0, 0, 0}; }

using stiff::random_unit;

TEST(Watertight, TessellatedSphereFarFromOriginNoMissesFromInside) {
  const dvec3 centre(148376.0, 1234.0, -223423.0);
  const double radius = 100.0;
  const int rings = 256, segments = 512;
  std::vector<vec3> verts;  // (rings + 1) x (segments + 1); the seam repeats the same floats
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j <= segments; ++j) {
      const double th = M_PI * i / rings, ph = 2.0 * M_PI * (j % segments) / segments;
      verts.push_back(vec3(centre + radius * dvec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph))));
    }
  Scene s;
  s.materials.resize(1);
  auto at = [&](int i, int j) { return verts[size_t(i) * (segments + 1) + j]; };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) s.triangles.push_back(tri(at(i, j), at(i, j + 1), at(i + 1, j)));
      if (i < rings - 1) s.triangles.push_back(tri(at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)));
    }
  const stiff::DeviceTracer tracer(s);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  // The 10^7 rays (10^4 on a simulator), traced in slices of 10^6
  // so the host arrays stay small.
  const size_t n = test::sized(10000000, 10000), slice = 1000000;
  size_t misses = 0, far = 0;
  for (size_t first = 0; first < n; first += slice) {
    const size_t m = std::min(slice, n - first);
    std::vector<vec3> o(m), d(m);
    for (size_t k = 0; k < m; ++k) {
      o[k] = vec3(centre + dvec3(float(0.5 * radius) * std::cbrt(u01(rng)) * random_unit(rng)));
      d[k] = random_unit(rng);
    }
    const std::vector<Hit> hits = tracer.closest(o, d);
    for (size_t k = 0; k < m; ++k) {
      if (hits[k].prim == PRIM_NONE) {
        ++misses;
        continue;
      }
      const double dist = glm::length(dvec3(o[k]) + double(hits[k].t) * dvec3(d[k]) - centre);
      far += std::fabs(dist - radius) > 0.1;  // chords of 1/256 of the circle sag by < 0.01
    }
  }
  std::printf("[measure] %zu triangles, %zu rays from inside: %zu misses\n", s.triangles.size(), n, misses);
  EXPECT_EQ(misses, 0u);
  EXPECT_EQ(far, 0u) << "hits off the sphere";
}

void grid_case(vec3 origin, vec3 ex, vec3 ey, uint32_t seed) {
  const int cells = 64;
  std::vector<vec3> verts;
  for (int i = 0; i <= cells; ++i)
    for (int j = 0; j <= cells; ++j) verts.push_back(origin + float(i) * ex + float(j) * ey);
  auto at = [&](int i, int j) { return verts[size_t(i) * (cells + 1) + j]; };
  Scene s;
  s.materials.resize(1);
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j) {
      s.triangles.push_back(tri(at(i, j), at(i + 1, j), at(i + 1, j + 1)));
      s.triangles.push_back(tri(at(i, j), at(i + 1, j + 1), at(i, j + 1)));
    }
  const stiff::DeviceTracer tracer(s);
  const vec3 normal = glm::normalize(glm::cross(ex, ey));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<vec3> o, d, target;
  // Interior vertices, and midpoints of interior edges (horizontal,
  // vertical, diagonal), each from one point above and one below.
  for (int i = 1; i < cells; ++i)
    for (int j = 1; j < cells; ++j) {
      const vec3 points[] = {at(i, j), 0.5f * (at(i, j) + at(i + 1, j)), 0.5f * (at(i, j) + at(i, j + 1)),
                             0.5f * (at(i, j) + at(i + 1, j + 1))};
      for (const vec3& p : points)
        for (float side : {1.0f, -1.0f}) {
          const float len = glm::length(ex) * cells;
          const vec3 from = p + len * (side * (0.2f + 0.5f * std::fabs(u(rng))) * normal +
                                       0.3f * (u(rng) * glm::normalize(ex) + u(rng) * glm::normalize(ey)));
          o.push_back(from);
          d.push_back(glm::normalize(p - from));
          target.push_back(p);
        }
    }
  const std::vector<Hit> hits = tracer.closest(o, d);
  size_t misses = 0, wrong = 0;
  for (size_t k = 0; k < o.size(); ++k) {
    if (hits[k].prim == PRIM_NONE) {
      ++misses;
      continue;
    }
    const float expect = glm::length(target[k] - o[k]);
    wrong += !(std::fabs(hits[k].t - expect) <= 1e-4f * expect + 1e-6f * glm::length(origin));
  }
  std::printf("[measure] grid at %.0f: %zu rays at shared vertices and edges, %zu misses, %zu off\n",
              glm::length(origin), o.size(), misses, wrong);
  EXPECT_EQ(misses, 0u);
  EXPECT_EQ(wrong, 0u);
}

TEST(Watertight, GridMeshSharedEdgesAndVerticesExactlyOneHit) {
  grid_case(vec3(-32.0f, -32.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 1);
  grid_case(vec3(1e4f, -2e4f, 5e3f), vec3(0.8f, 0.1f, 0.3f), vec3(-0.2f, 0.7f, 0.4f), 2);
}

}  // namespace
}  // namespace caustica
