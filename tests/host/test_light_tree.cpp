// Host tests of the light tree (issue 42): the builder
// (host/lights/light_tree.cpp) and the kernels' own traversal
// (kernels/lib/light_tree.h) compiled as C++.
//
// - Chi-square: on random trees of mixed lights (points, spots,
//   rectangles, one- and two-sided triangles, spheres, cylinders, textured
//   triangles by their mean texel), the lights light_tree_sample draws from
//   a shading point against light_tree_pmf, the probability MIS reads; and
//   the pmf it returns with each light is light_tree_pmf's, bit for bit.
// - The pmf of every light from a point sums to 1.
// - Conservative: a light that can light the point (in front of a
//   one-sided surface, inside a spot's cone, any omnidirectional light),
//   some of which is in front of the receiving surface, has a pmf above 0.
// - The packed normal the path carries for MIS: unit length, within 1e-4
//   radians of the normal packed.
// - Deterministic: the same lights give the same tree, node for node,
//   however many threads built it; trails stay within 64 levels.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "host/lights/light_tree.h"
#include "host/scene/scene.h"
#include "lib/light_normal.h"
#include "lib/light_tree.h"
#include "tests/support/chi_square.h"

namespace caustica {
namespace {

struct RandomLights {
  std::vector<Light> lights;
  std::vector<float> power;
};

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  glm::vec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// `count` lights of every kind with a position, spread over a box of side
// `extent`, powers over three decades.
RandomLights random_lights(int count, float extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  RandomLights out;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c = extent * glm::vec3(u01(rng), u01(rng), u01(rng));
    const float size = 0.02f * extent * (0.2f + u01(rng));
    Light l{};
    switch (i % 7) {
      case 0:
        l.kind = LIGHT_POINT;
        l.p0 = to_float4(c);
        break;
      case 1: {
        l.kind = LIGHT_SPOT;
        l.p0 = to_float4(c);
        const float cos_outer = 0.5f + 0.45f * u01(rng);
        l.p1 = to_float4(random_unit(rng), cos_outer);
        l.p2 = cs_float4{cos_outer + 0.5f * (1.0f - cos_outer), 1.0f - cos_outer, 0.0f, 0.0f};
        break;
      }
      case 2:
        l.kind = LIGHT_RECT;
        l.p0 = to_float4(c);
        l.p1 = to_float4(size * random_unit(rng));
        l.p2 = to_float4(size * random_unit(rng));
        break;
      case 3:
      case 4: {
        l.kind = LIGHT_TRIANGLE;
        l.p0 = to_float4(c);
        l.p1 = to_float4(c + size * random_unit(rng));
        l.p2 = to_float4(c + size * random_unit(rng));
        if (i % 7 == 4) l.flags = LIGHT_TWO_SIDED;
        break;
      }
      case 5:
        l.kind = LIGHT_SPHERE;
        l.p0 = to_float4(c, size);
        break;
      default:
        l.kind = LIGHT_CYLINDER;
        l.p0 = to_float4(c, 0.3f * size);
        l.p1 = to_float4(random_unit(rng), size);
        break;
    }
    out.lights.push_back(l);
    // Three decades of power; a textured triangle's is its mean texel's share.
    out.power.push_back(std::pow(10.0f, 3.0f * u01(rng)));
  }
  return out;
}

float pmf_of(const LightTree& tree, uint32_t light, const glm::vec3& p, const glm::vec3& n) {
  return light_tree_pmf(tree.nodes.data(), tree.trails[light], make_float3(p.x, p.y, p.z),
                        make_float3(n.x, n.y, n.z));
}

// Can light `l` send any light to p? (What the tree must never rule out.)
bool can_light(const Light& l, const glm::vec3& p) {
  switch (l.kind) {
    case LIGHT_SPOT: {
      const glm::vec3 w = glm::normalize(p - to_vec3(l.p0));
      return glm::dot(w, to_vec3(l.p1)) > l.p1.w + 1e-4f;
    }
    case LIGHT_RECT: {
      const glm::vec3 n = glm::cross(to_vec3(l.p1), to_vec3(l.p2));
      return glm::dot(p - to_vec3(l.p0), n) > 1e-4f * glm::length(n);
    }
    case LIGHT_TRIANGLE: {
      if (l.flags & LIGHT_TWO_SIDED) return true;
      const glm::vec3 n = glm::cross(to_vec3(l.p1) - to_vec3(l.p0), to_vec3(l.p2) - to_vec3(l.p0));
      // Some point of the triangle sees p in front (all three corners in its plane).
      return glm::dot(p - to_vec3(l.p0), n) > 1e-4f * glm::length(n);
    }
    default:
      return true;
  }
}

// Is some point of light `l` in front of the surface at p with normal n
// (zero n: no surface)? A light wholly behind it lights nothing there.
bool in_front(const Light& l, const glm::vec3& p, const glm::vec3& n) {
  if (glm::dot(n, n) == 0.0f) return true;
  const auto front = [&](const glm::vec3& q, float slack) { return glm::dot(q - p, n) > -slack + 1e-3f * glm::length(q - p); };
  const glm::vec3 c = to_vec3(l.p0);
  switch (l.kind) {
    case LIGHT_RECT: {
      const glm::vec3 u = 0.5f * to_vec3(l.p1), v = 0.5f * to_vec3(l.p2);
      return front(c - u - v, 0.0f) || front(c + u - v, 0.0f) || front(c + u + v, 0.0f) || front(c - u + v, 0.0f);
    }
    case LIGHT_TRIANGLE:
      return front(c, 0.0f) || front(to_vec3(l.p1), 0.0f) || front(to_vec3(l.p2), 0.0f);
    case LIGHT_SPHERE:
      return front(c, l.p0.w);
    case LIGHT_CYLINDER: {
      const glm::vec3 a = l.p1.w * to_vec3(l.p1);
      return front(c - a, l.p0.w) || front(c + a, l.p0.w);
    }
    default:
      return front(c, 0.0f);
  }
}

TEST(LightTree, PmfsSumToOneAndNeverRuleOutALightThatCanLightThePoint) {
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    const RandomLights r = random_lights(300, 10.0f, seed);
    const LightTree tree = build_light_tree(r.lights, r.power);
    ASSERT_EQ(tree.nodes.size(), 2 * r.lights.size() - 1);
    std::mt19937 rng(100 + seed);
    std::uniform_real_distribution<float> u(-2.0f, 12.0f);
    for (int k = 0; k < 50; ++k) {
      const glm::vec3 p(u(rng), u(rng), u(rng));
      const glm::vec3 n = k % 5 == 0 ? glm::vec3(0.0f) : random_unit(rng);
      double sum = 0.0;
      for (uint32_t i = 0; i < r.lights.size(); ++i) {
        const float pmf = pmf_of(tree, i, p, n);
        ASSERT_TRUE(std::isfinite(pmf) && pmf >= 0.0f);
        sum += pmf;
        if (can_light(r.lights[i], p) && in_front(r.lights[i], p, n))
          EXPECT_GT(pmf, 0.0f) << "light " << i << " (kind " << r.lights[i].kind << ") ruled out at point " << k;
      }
      EXPECT_NEAR(sum, 1.0, 1e-4) << "seed " << seed << ", point " << k;
    }
  }
}

TEST(LightTree, SamplesFollowThePmfChiSquare) {
  const int points = 12;
  int tests = 0;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const RandomLights r = random_lights(seed == 1 ? 40 : 200, 10.0f, seed);
    const LightTree tree = build_light_tree(r.lights, r.power);
    std::mt19937 rng(7 * seed);
    std::uniform_real_distribution<float> u(-2.0f, 12.0f), u01(0.0f, 1.0f);
    for (int k = 0; k < points; ++k, ++tests) {
      const glm::vec3 p(u(rng), u(rng), u(rng)), n = random_unit(rng);
      const float3 pf = make_float3(p.x, p.y, p.z), nf = make_float3(n.x, n.y, n.z);
      const int samples = 200000;
      std::vector<double> observed(r.lights.size(), 0.0), expected(r.lights.size(), 0.0);
      for (int s = 0; s < samples; ++s) {
        float pmf = 0.0f;
        const uint32_t light = light_tree_sample(tree.nodes.data(), pf, nf, u01(rng), &pmf);
        ASSERT_LT(light, r.lights.size());
        ASSERT_GT(pmf, 0.0f);
        observed[light] += 1.0;
        // The pmf sampling reports is the one MIS reads, to the bit.
        if (s % 64 == 0) {
          const float again = light_tree_pmf(tree.nodes.data(), tree.trails[light], pf, nf);
          ASSERT_EQ(std::memcmp(&pmf, &again, sizeof pmf), 0) << pmf << " vs " << again;
        }
      }
      for (uint32_t i = 0; i < r.lights.size(); ++i) expected[i] = samples * double(pmf_of(tree, i, p, n));
      test::ChiSquare result;
      test::chi_square_statistic(observed, expected, &result);
      EXPECT_GT(result.p, test::sidak(3 * points)) << "seed " << seed << ", point " << k << ": chi2 " << result.chi2
                                                   << " dof " << result.dof;
    }
  }
  EXPECT_EQ(tests, 3 * points);
}

TEST(LightTree, PackedNormalsStayWithinTheTreesSlack) {
  std::mt19937 rng(5);
  float worst = 0.0f;
  for (int k = 0; k < 200000; ++k) {
    glm::vec3 n = random_unit(rng);
    if (k < 6) n = glm::vec3(k % 3 == 0, k % 3 == 1, k % 3 == 2) * (k < 3 ? 1.0f : -1.0f);  // the axes
    const uint32_t packed = light_normal_pack(make_float3(n.x, n.y, n.z));
    ASSERT_NE(packed, LIGHT_NORMAL_NONE);
    const float3 m = light_normal_unpack(packed);
    ASSERT_NEAR(m.x * m.x + m.y * m.y + m.z * m.z, 1.0f, 1e-6f);
    // The angle from |cross| in double: a float dot product cannot resolve 1e-4 radians.
    const glm::dvec3 a(n), b(m.x, m.y, m.z);
    worst = std::max(worst, float(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b))));
  }
  EXPECT_LT(worst, 1e-4f);  // the importance allows 1e-3 radians
  const float3 none = light_normal_unpack(LIGHT_NORMAL_NONE);
  EXPECT_EQ(none.x * none.x + none.y * none.y + none.z * none.z, 0.0f);
}

TEST(LightTree, ASingleLightAndLightsAtInfinity) {
  RandomLights r = random_lights(1, 1.0f, 3);  // a point light
  Light sun{};
  sun.kind = LIGHT_DIRECTIONAL;
  r.lights.push_back(sun);
  r.power.push_back(5.0f);
  const LightTree tree = build_light_tree(r.lights, r.power);
  ASSERT_EQ(tree.nodes.size(), 1u);
  EXPECT_EQ(tree.lights, std::vector<uint32_t>{0u});
  EXPECT_EQ(tree.trails[1].depth, 0u);
  float pmf = 0.0f;
  EXPECT_EQ(light_tree_sample(tree.nodes.data(), make_float3(3, 3, 3), make_float3(0, 1, 0), 0.7f, &pmf), 0u);
  EXPECT_EQ(pmf, 1.0f);
  EXPECT_EQ(pmf_of(tree, 0, glm::vec3(3.0f), glm::vec3(0, 1, 0)), 1.0f);
}

TEST(LightTree, TheSameLightsGiveTheSameTree) {
  // 20000 lights: the top levels build on two threads.
  const RandomLights r = random_lights(20000, 100.0f, 11);
  const LightTree a = build_light_tree(r.lights, r.power);
  const LightTree b = build_light_tree(r.lights, r.power);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(LightTreeNode)), 0);
  EXPECT_EQ(std::memcmp(a.trails.data(), b.trails.data(), a.trails.size() * sizeof(LightTreeTrail)), 0);
  EXPECT_LE(a.max_depth, int(LIGHT_TREE_MAX_DEPTH));
  // Every node's power is its children's sum; every light is one leaf.
  std::vector<int> leaves(r.lights.size(), 0);
  for (uint32_t i = 0; i < a.nodes.size(); ++i) {
    const LightTreeNode& node = a.nodes[i];
    if (node.flags & LIGHT_TREE_LEAF) {
      ++leaves[node.index];
      continue;
    }
    const float sum = a.nodes[i + 1].bounds_min.w + a.nodes[node.index].bounds_min.w;
    EXPECT_NEAR(node.bounds_min.w, sum, 1e-5f * sum);
  }
  for (int count : leaves) EXPECT_EQ(count, 1);
}

}  // namespace
}  // namespace caustica
