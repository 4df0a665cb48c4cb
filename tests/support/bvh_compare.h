// Shared by test_bvh.cpp and test_sbvh.cpp: random scenes and rays, and the
// check that device traversal of a wide BVH equals brute force over every
// primitive (the same primitive tests), for closest-hit and any-hit queries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "host/scene/scene.h"

namespace caustica::test {

struct Rng {
  std::mt19937 gen;
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  glm::vec3 in_box(float h) { return glm::vec3(uniform(-h, h), uniform(-h, h), uniform(-h, h)); }
  glm::vec3 unit() {
    std::normal_distribution<float> g;
    return glm::normalize(glm::vec3(g(gen), g(gen), g(gen)));
  }
};

Triangle triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// Random primitives scattered over the cube [-10, 10]^3.
void add_spheres(Scene& s, Rng& rng, int n);
void add_cylinders(Scene& s, Rng& rng, int n);
void add_small_triangles(Scene& s, Rng& rng, int n);
// add_small_triangles plus a closed axis-aligned room around them: its walls
// have flat boxes and shared edges, and they span the scene, so every object
// split overlaps them and spatial splits chop them.
void add_triangles(Scene& s, Rng& rng, int n);

// Index of a primitive among all of the scene's: spheres, cylinders, triangles.
size_t flat_index(const Scene& s, uint32_t ref);
// One reference per primitive: brute force must not loop over a BVH's
// references, which may repeat a triangle.
std::vector<uint32_t> one_ref_per_primitive(const Scene& s);
// A point inside primitive `p` (a flat index).
glm::vec3 point_in(const Scene& s, size_t p, Rng& rng);
bool node_contains(const BvhNode& outer, const BvhNode& inner);

// Walks a binary BVH from the root checking what every build must hold:
// depth-first layout (left child next, right child after it), children
// inside their parent, leaves of at most max_leaf references within
// prim_refs, every node reached once, depth as recorded and within the
// traversal's limit. Calls leaf(index, node) for each leaf, whose contents
// the caller checks.
void walk_binary_bvh(const Bvh& bvh, int max_leaf, const std::function<void(uint32_t, const BvhNode&)>& leaf);

struct Ray {
  glm::vec3 o, d;
  float tmin, tmax_any;
};

// Whether a quarter of the rays go through random points of random
// primitives, which finds thin triangles that random rays would miss.
enum class AimAtPrimitives { No, Yes };

// Origins inside and outside the scene; some directions with exactly zero
// components (the clamped reciprocal path); some rays with tmin > 0; some
// aimed exactly at triangle vertices, which lie on their boxes' corners where
// slab-test rounding must not cull the hit.
std::vector<Ray> random_rays(Rng& rng, int n, const Scene& s, AimAtPrimitives aim = AimAtPrimitives::No);

struct Outcome {
  float bvh_t, brute_t;
  uint32_t bvh_prim, brute_prim;
  bool any;
};

// Builds of the comparison kernel. The renderer may build with
// -cl-fast-relaxed-math: traversal must stay exact with respect to brute
// force under both. SmallStack shrinks the traversal stack to
// kSmallStackSize so that nodes fall back to group entries
// (bvh_traverse.h) far more often than with the real size.
// PortableLanes: the lane sets GPUs use (bvh_traverse.h picks bit lanes on
// x86 CPUs), with the small stack so that their group entries run too.
enum class KernelBuild { Plain, FastRelaxedMath, SmallStack, PortableLanes };
constexpr int kSmallStackSize = 10;
std::string build_options(KernelBuild build);

// Traces every ray through `bvh` and by brute force on the device.
std::vector<Outcome> run_compare(const Scene& s, const WideBvh& bvh, const std::vector<Ray>& rays, KernelBuild build);

// Closest hits equal brute force (ties in t may pick either primitive), any
// hits agree with the closest t against tmax_any, and at least a fifth of
// the rays hit something so that the comparison is not vacuous.
void expect_outcomes(const std::vector<Ray>& rays, const std::vector<Outcome>& outcomes);

// run_compare and expect_outcomes for each of `builds`. A tree too deep for
// the SmallStack build fails rather than being traced with a stack it overflows.
void expect_matches_brute_force(const Scene& s, const WideBvh& bvh, const std::vector<Ray>& rays,
                                std::initializer_list<KernelBuild> builds);

}  // namespace caustica::test
