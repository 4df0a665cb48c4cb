// BVH builder invariants on the host, and traversal on the device checked
// against brute force (the same primitive tests over every primitive) for
// random scenes of each primitive type and a mixed one.
#include <cstring>
#include <glm/glm.hpp>
#include <random>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::vec3;
using test::runtime;

const char* kCompareKernel = R"CLC(
#include "lib/bvh_traverse.h"

__kernel void compare(SCENE_GEOMETRY_PARAMS, __global const uint* all_refs, uint prim_count,
                      __global const float4* rays, uint ray_count, __global float4* out) {
  uint i = get_global_id(0);
  if (i >= ray_count) return;
  float4 o = rays[2 * i], d = rays[2 * i + 1]; /* o.w = tmin, d.w = tmax of the any-hit query */
  Hit bvh = trace_closest(SCENE_GEOMETRY_ARGS, o.xyz, d.xyz, o.w, RAY_T_FAR);
  Hit brute = hit_none(RAY_T_FAR);
  for (uint p = 0; p < prim_count; ++p)
    intersect_prim_ref(spheres, cylinders, triangles, all_refs[p], o.xyz, d.xyz, o.w, &brute);
  bool any = trace_any(SCENE_GEOMETRY_ARGS, o.xyz, d.xyz, o.w, d.w);
  out[i] = (float4)(bvh.t, as_float(bvh.prim), brute.t, as_float(brute.prim));
  out[ray_count + i] = (float4)(any ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f);
}
)CLC";

struct Ray {
  vec3 o, d;
  float tmin, tmax_any;
};

struct Outcome {
  float bvh_t, brute_t;
  uint32_t bvh_prim, brute_prim;
  bool any;
};

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

template <class T>
cl::Buffer upload(std::vector<T> v) {
  if (v.empty()) v.resize(1);  // OpenCL refuses zero-sized buffers
  return cl::Buffer(runtime().context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T), v.data());
}

// The renderer may build with -cl-fast-relaxed-math: traversal must stay
// exact with respect to brute force under both. The third variant shrinks
// the traversal stack so that nodes fall back to group entries
// (bvh_traverse.h) far more often than with the real size.
const char* const kBuildOptions[] = {"", "-cl-fast-relaxed-math", "-DBVH_STACK_SIZE=10"};
constexpr int kSmallStack = 10;

std::vector<uint32_t> all_refs(const Scene& s) {
  std::vector<uint32_t> refs;
  for (size_t i = 0; i < s.spheres.size(); ++i) refs.push_back(PRIM_SPHERE << PRIM_TYPE_SHIFT | uint32_t(i));
  for (size_t i = 0; i < s.cylinders.size(); ++i) refs.push_back(PRIM_CYLINDER << PRIM_TYPE_SHIFT | uint32_t(i));
  for (size_t i = 0; i < s.triangles.size(); ++i) refs.push_back(PRIM_TRIANGLE << PRIM_TYPE_SHIFT | uint32_t(i));
  return refs;
}

std::vector<Outcome> run_compare(const Scene& s, const WideBvh& bvh, const std::vector<Ray>& rays, int variant) {
  static cl::Program programs[3];
  cl::Program& program = programs[variant];
  if (!program())
    program = runtime()
                  .build_source("test_bvh.cl", kCompareKernel,
                                std::string("-DHAS_SPHERES -DHAS_CYLINDERS -DHAS_TRIANGLES ") + kBuildOptions[variant])
                  .program;
  std::vector<cs_float4> data;
  for (const Ray& r : rays) {
    data.push_back(to_float4(r.o, r.tmin));
    data.push_back(to_float4(r.d, r.tmax_any));
  }
  const size_t n = rays.size();
  const std::vector<uint32_t> refs = all_refs(s);
  cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, 2 * n * sizeof(cs_float4));
  // The kernel does not retain its buffers: keep them alive until the read.
  std::vector<cl::Buffer> keep = {upload(bvh.nodes),   upload(bvh.triangle_blocks), upload(bvh.prim_refs),
                                  upload(s.spheres),   upload(s.cylinders),         upload(s.triangles),
                                  upload(refs),        upload(data)};
  cl::Kernel k(program, "compare");
  for (int a = 0; a < 7; ++a) k.setArg(a, keep[a]);
  k.setArg(7, static_cast<cl_uint>(refs.size()));
  k.setArg(8, keep[7]);
  k.setArg(9, static_cast<cl_uint>(n));
  k.setArg(10, out);
  runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
  std::vector<cs_float4> o(2 * n);
  runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, o.size() * sizeof(cs_float4), o.data());
  std::vector<Outcome> result(n);
  for (size_t i = 0; i < n; ++i) result[i] = {o[i].x, o[i].z, bits(o[i].y), bits(o[i].w), o[n + i].x > 0.5f};
  return result;
}

struct Rng {
  std::mt19937 gen;
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  vec3 in_box(float h) { return vec3(uniform(-h, h), uniform(-h, h), uniform(-h, h)); }
  vec3 unit() {
    std::normal_distribution<float> g;
    return glm::normalize(vec3(g(gen), g(gen), g(gen)));
  }
};

void add_spheres(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i)
    s.spheres.push_back(Sphere{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.6f)), 0, 0, 0, 0});
}
void add_cylinders(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i)
    s.cylinders.push_back(Cylinder{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.4f)),
                                   to_float4(rng.unit(), rng.uniform(0.1f, 1.2f)), 0, 0, 0, 0});
}
// Random small triangles plus a closed axis-aligned room, whose walls have
// flat boxes and shared edges.
void add_triangles(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i) {
    const vec3 c = rng.in_box(10);
    const float size = rng.uniform(0.1f, 1.5f);
    s.triangles.push_back(Triangle{to_float4(c + size * rng.unit()), to_float4(c + size * rng.unit()),
                                   to_float4(c + size * rng.unit()), 0, 0, 0, 0});
  }
  const float w = 11.0f;
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-w, w}) {
      vec3 q[4];
      for (int k = 0; k < 4; ++k) {
        q[k][axis] = side;
        q[k][(axis + 1) % 3] = (k == 1 || k == 2) ? w : -w;
        q[k][(axis + 2) % 3] = k >= 2 ? w : -w;
      }
      s.triangles.push_back(Triangle{to_float4(q[0]), to_float4(q[1]), to_float4(q[2]), 0, 0, 0, 0});
      s.triangles.push_back(Triangle{to_float4(q[0]), to_float4(q[2]), to_float4(q[3]), 0, 0, 0, 0});
    }
}

// Origins inside and outside the scene; some directions with exactly zero
// components (the clamped reciprocal path); some rays with tmin > 0; some
// aimed exactly at triangle vertices, which lie on their boxes' corners where
// slab-test rounding must not cull the hit.
std::vector<Ray> random_rays(Rng& rng, int n, const Scene& s) {
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    Ray r;
    r.o = i % 2 ? rng.in_box(12) : 30.0f * rng.unit();
    r.d = i % 2 ? rng.unit() : glm::normalize(rng.in_box(8) - r.o);
    if (i % 4 == 1 && !s.triangles.empty()) {
      const Triangle& t = s.triangles[rng.gen() % s.triangles.size()];
      const cs_float4 v = i % 3 == 0 ? t.v0 : (i % 3 == 1 ? t.v1 : t.v2);
      r.o = to_vec3(v) - rng.uniform(0.5f, 20.0f) * r.d;
      r.d = to_vec3(v) - r.o;  // not normalised: t = 1 is the vertex exactly
    }
    if (i % 10 == 3) r.d[i % 3] = 0.0f;
    if (i % 10 == 7) {
      r.d = vec3(0.0f);
      r.d[i % 3] = (i % 20 < 10) ? 1.0f : -1.0f;
    }
    r.d = i % 4 == 1 ? r.d : glm::normalize(r.d);
    r.tmin = i % 5 == 0 ? rng.uniform(0.0f, 5.0f) : 0.0f;
    r.tmax_any = rng.uniform(0.0f, 40.0f);
    rays.push_back(r);
  }
  return rays;
}

void expect_traversal_matches_brute_force(const Scene& s, int ray_count, uint32_t seed,
                                          const BvhBuildOptions& options = {}) {
  const Bvh binary = build_bvh(s, options);
  const WideBvh bvh = collapse_bvh(binary, s);
  Rng rng{std::mt19937(seed)};
  const auto rays = random_rays(rng, ray_count, s);
  ASSERT_LT(bvh.height, kSmallStack);  // else the small-stack variant would not be a valid build
  for (int variant = 0; variant < 3; ++variant) {
    SCOPED_TRACE(std::string("build options: ") + kBuildOptions[variant]);
    const auto out = run_compare(s, bvh, rays, variant);
    int closest_bad = 0, any_bad = 0, hits = 0;
    for (size_t i = 0; i < out.size(); ++i) {
      const Outcome& o = out[i];
      const bool hit = o.brute_prim != PRIM_NONE;
      hits += hit;
      // Equal t with different prims is a tie the traversal may break either way.
      if (((o.bvh_prim != PRIM_NONE) != hit ||
           (hit && std::abs(o.bvh_t - o.brute_t) > 1e-6f * std::max(1.0f, o.brute_t))) &&
          ++closest_bad <= 5)
        ADD_FAILURE() << "ray " << i << ": bvh prim " << o.bvh_prim << " t " << o.bvh_t << ", brute prim "
                      << o.brute_prim << " t " << o.brute_t;
      const float tmax = rays[i].tmax_any;
      if (hit && std::abs(o.brute_t - tmax) <= 1e-5f * tmax) continue;  // too close to call
      if (o.any != (hit && o.brute_t < tmax) && ++any_bad <= 5)
        ADD_FAILURE() << "ray " << i << ": any-hit " << o.any << " but closest t " << o.brute_t << " tmax " << tmax;
    }
    EXPECT_EQ(closest_bad, 0);
    EXPECT_EQ(any_bad, 0);
    EXPECT_GT(hits, ray_count / 5);  // the comparison must not be vacuous
  }
}

struct Mix {
  const char* name;
  int spheres, cylinders, triangles;
};

class BvhTraversal : public ::testing::TestWithParam<Mix> {};

TEST_P(BvhTraversal, MatchesBruteForce) {
  const Mix& m = GetParam();
  Scene s;
  Rng rng{std::mt19937(m.spheres + 7 * m.cylinders + 13 * m.triangles)};
  add_spheres(s, rng, m.spheres);
  add_cylinders(s, rng, m.cylinders);
  if (m.triangles > 0) add_triangles(s, rng, m.triangles);
  expect_traversal_matches_brute_force(s, 12000, 101);
}

INSTANTIATE_TEST_SUITE_P(Scenes, BvhTraversal,
                         ::testing::Values(Mix{"Spheres", 3000, 0, 0}, Mix{"Cylinders", 0, 3000, 0},
                                           Mix{"Triangles", 0, 0, 4000}, Mix{"Mixed", 1200, 1200, 1200}),
                         [](const auto& info) { return std::string(info.param.name); });

bool point_inside(const vec3& p, const BvhNode& n) {
  return p.x >= n.lo_x && p.y >= n.lo_y && p.z >= n.lo_z && p.x <= n.hi_x && p.y <= n.hi_y && p.z <= n.hi_z;
}

// Extreme points of each primitive (cylinders: points around both rims).
bool prim_inside(const Scene& s, uint32_t type, uint32_t idx, const BvhNode& n) {
  std::vector<vec3> points;
  if (type == PRIM_SPHERE) {
    const cs_float4 c = s.spheres[idx].center_radius;
    for (int a = 0; a < 6; ++a)
      points.push_back(to_vec3(c) + (a < 3 ? c.w : -c.w) * vec3(a % 3 == 0, a % 3 == 1, a % 3 == 2));
  } else if (type == PRIM_TRIANGLE) {
    points = {to_vec3(s.triangles[idx].v0), to_vec3(s.triangles[idx].v1), to_vec3(s.triangles[idx].v2)};
  } else {
    const Cylinder& c = s.cylinders[idx];
    const vec3 a = to_vec3(c.axis_half),
               e1 = glm::normalize(glm::cross(a, std::abs(a.x) > 0.5f ? vec3(0, 1, 0) : vec3(1, 0, 0)));
    for (int k = 0; k < 128; ++k) {
      const float phi = 6.2831853f * (k / 2) / 64, sign = k % 2 ? 1.0f : -1.0f;
      const vec3 rim = 0.9999f * c.center_radius.w * (std::cos(phi) * e1 + std::sin(phi) * glm::cross(a, e1));
      points.push_back(to_vec3(c.center_radius) + sign * 0.9999f * c.axis_half.w * a + rim);
    }
  }
  for (const vec3& p : points)
    if (!point_inside(p, n)) return false;
  return true;
}

// Structural invariants: depth-first layout, containment, each primitive in
// exactly one leaf, depth within the traversal stack.
void check_structure(const Scene& s, const Bvh& bvh, int max_leaf) {
  ASSERT_FALSE(bvh.nodes.empty());
  std::vector<int> seen(s.primitive_count(), 0);
  int max_depth = 0;
  struct Item {
    uint32_t node;
    int depth;
  };
  std::vector<Item> todo = {{0, 0}};
  size_t visited = 0;
  auto inside = [](const BvhNode& c, const BvhNode& p) {
    return c.lo_x >= p.lo_x && c.lo_y >= p.lo_y && c.lo_z >= p.lo_z && c.hi_x <= p.hi_x && c.hi_y <= p.hi_y &&
           c.hi_z <= p.hi_z;
  };
  while (!todo.empty()) {
    const Item it = todo.back();
    todo.pop_back();
    ++visited;
    const BvhNode& n = bvh.nodes[it.node];
    max_depth = std::max(max_depth, it.depth);
    if (n.count > 0) {
      ASSERT_LE(n.count, static_cast<uint32_t>(max_leaf));
      ASSERT_LE(n.offset + n.count, bvh.prim_refs.size());
      for (uint32_t i = n.offset; i < n.offset + n.count; ++i) {
        const uint32_t ref = bvh.prim_refs[i], type = ref >> PRIM_TYPE_SHIFT, idx = ref & PRIM_INDEX_MASK;
        size_t flat =
            idx + (type >= PRIM_CYLINDER ? s.spheres.size() : 0) + (type == PRIM_TRIANGLE ? s.cylinders.size() : 0);
        ASSERT_LT(flat, seen.size());
        ++seen[flat];
        EXPECT_TRUE(prim_inside(s, type, idx, n)) << "primitive " << ref << " outside its leaf box";
      }
      continue;
    }
    const uint32_t left = it.node + 1, right = n.offset;
    ASSERT_GT(right, left);
    ASSERT_LT(right, bvh.nodes.size());
    EXPECT_TRUE(inside(bvh.nodes[left], n) && inside(bvh.nodes[right], n)) << "node " << it.node;
    todo.push_back({right, it.depth + 1});
    todo.push_back({left, it.depth + 1});
  }
  EXPECT_EQ(visited, bvh.nodes.size());
  for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;
  EXPECT_EQ(max_depth, bvh.max_depth);
  EXPECT_LE(max_depth, kBvhMaxDepth);
}

TEST(BvhBuild, StructureOfRandomScenes) {
  Scene s;
  Rng rng{std::mt19937(9)};
  add_spheres(s, rng, 3000);
  add_cylinders(s, rng, 3000);
  add_triangles(s, rng, 3000);
  const Bvh bvh = build_bvh(s);
  check_structure(s, bvh, 4);
  EXPECT_GT(bvh.sah_cost, 1.0);
  EXPECT_LT(bvh.sah_cost, 0.02 * s.primitive_count());  // far better than one big leaf
  // Cylinder boxes are tight: a cylinder along x is no wider than its radius.
  Scene c;
  c.cylinders.push_back(Cylinder{to_float4(vec3(0.0f), 0.5f), to_float4(vec3(1, 0, 0), 2.0f), 0, 0, 0, 0});
  const BvhNode root = build_bvh(c).nodes[0];
  EXPECT_NEAR(root.hi_x, 2.0f, 1e-6f);
  EXPECT_NEAR(root.hi_y, 0.5f, 1e-6f);
  EXPECT_NEAR(root.lo_z, -0.5f, 1e-6f);
}

TEST(BvhBuild, DegenerateCentroids) {
  Scene same;  // identical centroids: no SAH plane separates anything
  for (int i = 0; i < 1000; ++i) same.spheres.push_back(Sphere{to_float4(vec3(1, 2, 3), 0.5f), 0, 0, 0, 0});
  check_structure(same, build_bvh(same), 4);
}

// Random scenes never get near depth 64, so the median-split fallback is
// exercised with a lower limit: the tree must obey it and still trace right.
TEST(BvhBuild, DepthLimitFallsBackToMedianSplits) {
  Scene s;
  Rng rng{std::mt19937(12)};
  add_spheres(s, rng, 1500);
  add_triangles(s, rng, 1500);
  ASSERT_GT(build_bvh(s).max_depth, 12);
  BvhBuildOptions limited;
  limited.max_depth = 12;
  const Bvh bvh = build_bvh(s, limited);
  check_structure(s, bvh, 4);  // 2^12 leaves are room enough for 3,012 primitives
  EXPECT_LE(bvh.max_depth, 12);
  limited.max_depth = 8;
  const Bvh shallow = build_bvh(s, limited);
  check_structure(s, shallow, 64);  // too shallow for 4 per leaf: leaves grow instead
  EXPECT_EQ(shallow.max_depth, 8);
  expect_traversal_matches_brute_force(s, 4000, 106, limited);
}

// Leaves of hundreds of primitives: the wide BVH splits them into chunks of
// blocks and refs under nodes of their own (test_bvh_wide.cpp checks the
// structure); traversal through those must still match brute force.
TEST(BvhBuild, HugeLeavesTraceRight) {
  Scene s;
  Rng rng{std::mt19937(14)};
  add_spheres(s, rng, 500);
  add_cylinders(s, rng, 500);
  add_triangles(s, rng, 1000);
  BvhBuildOptions shallow;
  shallow.max_depth = 2;
  expect_traversal_matches_brute_force(s, 3000, 107, shallow);
}

TEST(BvhBuild, EmptySceneMisses) {
  const Scene s;
  const Bvh bvh = build_bvh(s);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_TRUE(bvh.prim_refs.empty());
  EXPECT_EQ(bvh.nodes[0].count, 0u);
  EXPECT_EQ(bvh.nodes[0].lo_x, 1e18f);
  EXPECT_EQ(bvh.nodes[0].hi_z, -1e18f);
  const WideBvh wide = collapse_bvh(bvh, s);
  ASSERT_EQ(wide.nodes.size(), 1u);
  for (uint32_t c : wide.nodes[0].child) EXPECT_EQ(c, WIDE_CHILD_EMPTY);
  Rng rng{std::mt19937(6)};
  for (const Outcome& o : run_compare(s, wide, random_rays(rng, 256, s), 1)) {
    EXPECT_EQ(o.bvh_prim, PRIM_NONE);
    EXPECT_FALSE(o.any);
  }
}

// Primitive code is cut by HAS_* flags: every subset, none included, must
// compile (the renderer builds only what the scene needs).
TEST(BvhKernels, CompileForEveryPrimitiveSubset) {
  const char* kernel = R"CLC(
#include "lib/bvh_traverse.h"
#include "lib/surface.h"
__kernel void k(SCENE_GEOMETRY_PARAMS, __global float4* out) {
  float3 o = (float3)(0.0f), d = (float3)(0.0f, 0.0f, 1.0f);
  Hit h = trace_closest(SCENE_GEOMETRY_ARGS, o, d, 0.0f, RAY_T_FAR);
  SurfacePoint sp = surface_at(spheres, cylinders, triangles, (__global const TriangleShading*)0, h, o, d);
  out[0] = (float4)(sp.position, trace_any(SCENE_GEOMETRY_ARGS, o, d, 0.0f, 1.0f) ? 1.0f : 0.0f);
}
)CLC";
  for (const char* options : {"", "-DHAS_SPHERES", "-DHAS_CYLINDERS", "-DHAS_TRIANGLES -cl-fast-relaxed-math"})
    EXPECT_NO_THROW(runtime().build_source("test_bvh_subset.cl", kernel, options)) << options;
}

TEST(BvhBuild, FastEnoughForLargeScenes) {
  Scene s;
  Rng rng{std::mt19937(8)};
  add_spheres(s, rng, 6400);
  add_cylinders(s, rng, 6400);
  const Bvh small = build_bvh(s);
  s = Scene{};
  add_triangles(s, rng, 350000);
  const Bvh large = build_bvh(s);
  std::printf("12,800 prims: %.1f ms (SAH %.1f); 350k triangles: %.1f ms (SAH %.1f, depth %d)\n", small.build_ms,
              small.sah_cost, large.build_ms, large.sah_cost, large.max_depth);
  EXPECT_LT(small.build_ms, 500.0);
  EXPECT_LT(large.build_ms, 5000.0);
}

}  // namespace
}  // namespace caustica
