// Random scenes and rays for the BVH tests, and the device kernel that
// compares BVH traversal with brute force (tests/kernels/support/
// bvh_compare.cl; see bvh_compare.h).
#include "tests/support/bvh_compare.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "tests/support/test_support.h"

namespace caustica::test {
namespace {

using glm::vec3;

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

template <class T, class Allocator>
cl::Buffer upload(std::vector<T, Allocator> v) {
  if (v.empty()) v.resize(1);  // OpenCL refuses zero-sized buffers
  return cl::Buffer(runtime().context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T), v.data());
}

}  // namespace

Triangle triangle(const vec3& a, const vec3& b, const vec3& c) {
  return Triangle{to_float4(a), to_float4(b), to_float4(c), 0, 0, 0, 0};
}

void add_spheres(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i)
    s.spheres.push_back(Sphere{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.6f)), 0, 0, 0, 0});
}

void add_cylinders(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i)
    s.cylinders.push_back(Cylinder{to_float4(rng.in_box(10), rng.uniform(0.05f, 0.4f)),
                                   to_float4(rng.unit(), rng.uniform(0.1f, 1.2f)), 0, 0, 0, 0});
}

void add_small_triangles(Scene& s, Rng& rng, int n) {
  for (int i = 0; i < n; ++i) {
    const vec3 c = rng.in_box(10);
    const float size = rng.uniform(0.1f, 1.5f);
    s.triangles.push_back(triangle(c + size * rng.unit(), c + size * rng.unit(), c + size * rng.unit()));
  }
}

void add_triangles(Scene& s, Rng& rng, int n) {
  add_small_triangles(s, rng, n);
  const float w = 11.0f;
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-w, w}) {
      vec3 q[4];
      for (int k = 0; k < 4; ++k) {
        q[k][axis] = side;
        q[k][(axis + 1) % 3] = (k == 1 || k == 2) ? w : -w;
        q[k][(axis + 2) % 3] = k >= 2 ? w : -w;
      }
      s.triangles.push_back(triangle(q[0], q[1], q[2]));
      s.triangles.push_back(triangle(q[0], q[2], q[3]));
    }
}

size_t flat_index(const Scene& s, uint32_t ref) {
  const uint32_t type = ref >> PRIM_TYPE_SHIFT, idx = ref & PRIM_INDEX_MASK;
  return idx + (type >= PRIM_CYLINDER ? s.spheres.size() : 0) + (type == PRIM_TRIANGLE ? s.cylinders.size() : 0);
}

std::vector<uint32_t> one_ref_per_primitive(const Scene& s) {
  std::vector<uint32_t> refs;
  for (size_t i = 0; i < s.spheres.size(); ++i) refs.push_back(PRIM_SPHERE << PRIM_TYPE_SHIFT | uint32_t(i));
  for (size_t i = 0; i < s.cylinders.size(); ++i) refs.push_back(PRIM_CYLINDER << PRIM_TYPE_SHIFT | uint32_t(i));
  for (size_t i = 0; i < s.triangles.size(); ++i) refs.push_back(PRIM_TRIANGLE << PRIM_TYPE_SHIFT | uint32_t(i));
  return refs;
}

vec3 point_in(const Scene& s, size_t p, Rng& rng) {
  if (p < s.spheres.size()) return to_vec3(s.spheres[p].center_radius);
  p -= s.spheres.size();
  if (p < s.cylinders.size()) return to_vec3(s.cylinders[p].center_radius);
  p -= s.cylinders.size();
  const Triangle& t = s.triangles[p];
  float u = rng.uniform(0.05f, 0.9f), v = rng.uniform(0.05f, 0.9f);
  if (u + v > 0.95f) u = 0.95f - u, v = 0.95f - v;
  u = std::max(u, 0.02f), v = std::max(v, 0.02f);
  return (1.0f - u - v) * to_vec3(t.v0) + u * to_vec3(t.v1) + v * to_vec3(t.v2);
}

bool node_contains(const BvhNode& outer, const BvhNode& inner) {
  return inner.lo_x >= outer.lo_x && inner.lo_y >= outer.lo_y && inner.lo_z >= outer.lo_z &&
         inner.hi_x <= outer.hi_x && inner.hi_y <= outer.hi_y && inner.hi_z <= outer.hi_z;
}

void walk_binary_bvh(const Bvh& bvh, int max_leaf, const std::function<void(uint32_t, const BvhNode&)>& leaf) {
  ASSERT_FALSE(bvh.nodes.empty());
  int max_depth = 0;
  struct Item {
    uint32_t node;
    int depth;
  };
  std::vector<Item> todo = {{0, 0}};
  size_t visited = 0;
  while (!todo.empty()) {
    const Item it = todo.back();
    todo.pop_back();
    ++visited;
    const BvhNode& n = bvh.nodes[it.node];
    max_depth = std::max(max_depth, it.depth);
    if (n.count > 0) {
      ASSERT_LE(n.count, static_cast<uint32_t>(max_leaf));
      ASSERT_LE(n.offset + n.count, bvh.prim_refs.size());
      leaf(it.node, n);
      continue;
    }
    const uint32_t left = it.node + 1, right = n.offset;
    ASSERT_GT(right, left);
    ASSERT_LT(right, bvh.nodes.size());
    EXPECT_TRUE(node_contains(n, bvh.nodes[left]) && node_contains(n, bvh.nodes[right])) << "node " << it.node;
    todo.push_back({right, it.depth + 1});
    todo.push_back({left, it.depth + 1});
  }
  EXPECT_EQ(visited, bvh.nodes.size());
  EXPECT_EQ(max_depth, bvh.max_depth);
  EXPECT_LE(max_depth, kBvhMaxDepth);
}

std::vector<Ray> random_rays(Rng& rng, int n, const Scene& s, AimAtPrimitives aim) {
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
    if (aim == AimAtPrimitives::Yes && i % 4 == 2 && s.primitive_count() > 0)
      r.d = glm::normalize(point_in(s, rng.gen() % s.primitive_count(), rng) - r.o);
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

std::string build_options(KernelBuild build) {
  switch (build) {
    case KernelBuild::Plain: return "";
    case KernelBuild::FastRelaxedMath: return "-cl-fast-relaxed-math";
    case KernelBuild::SmallStack: return "-DBVH_STACK_SIZE=" + std::to_string(kSmallStackSize);
    case KernelBuild::PortableLanes:
      return "-DBVH8_PORTABLE_LANES -DBVH_STACK_SIZE=" + std::to_string(kSmallStackSize);
  }
  return "";
}

std::vector<Outcome> run_compare(const Scene& s, const WideBvh& bvh, const std::vector<Ray>& rays, KernelBuild build) {
  // One per KernelBuild; never released (test::runtime() says why).
  constexpr int kBuilds = static_cast<int>(KernelBuild::PortableLanes) + 1;
  static cl::Program* programs = new cl::Program[kBuilds];
  cl::Program& program = programs[static_cast<int>(build)];
  if (!program()) {
    const std::string options = "-DHAS_SPHERES -DHAS_CYLINDERS -DHAS_TRIANGLES " + build_options(build);
    program = build_test_kernel("support/bvh_compare.cl", options).program;
  }
  std::vector<cs_float4> data;
  for (const Ray& r : rays) {
    data.push_back(to_float4(r.o, r.tmin));
    data.push_back(to_float4(r.d, r.tmax_any));
  }
  const size_t n = rays.size();
  const std::vector<uint32_t> all_refs = one_ref_per_primitive(s);
  cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, 2 * n * sizeof(cs_float4));
  // The kernel does not retain its buffers: keep them alive until the read.
  // No alpha cut-outs (HAS_ALPHA_CUTOUTS 0): a dummy record and texel.
  std::vector<cl::Buffer> keep = {upload(bvh.nodes),   upload(bvh.triangle_blocks), upload(bvh.prim_refs),
                                  upload(s.spheres),   upload(s.cylinders),         upload(s.triangles),
                                  upload(std::vector<TriangleAlpha>(1)), upload(std::vector<uint16_t>(4)),
                                  upload(all_refs),    upload(data)};
  cl::Kernel k(program, "compare");
  for (int a = 0; a < 9; ++a) k.setArg(a, keep[a]);
  k.setArg(9, static_cast<cl_uint>(all_refs.size()));
  k.setArg(10, keep[9]);
  k.setArg(11, static_cast<cl_uint>(n));
  k.setArg(12, out);
  runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
  std::vector<cs_float4> o(2 * n);
  runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, o.size() * sizeof(cs_float4), o.data());
  std::vector<Outcome> result(n);
  for (size_t i = 0; i < n; ++i) result[i] = {o[i].x, o[i].z, bits(o[i].y), bits(o[i].w), o[n + i].x > 0.5f};
  return result;
}

void expect_outcomes(const std::vector<Ray>& rays, const std::vector<Outcome>& outcomes) {
  ASSERT_EQ(outcomes.size(), rays.size());
  int closest_bad = 0, any_bad = 0, hits = 0;
  for (size_t i = 0; i < outcomes.size(); ++i) {
    const Outcome& o = outcomes[i];
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
  EXPECT_GT(hits, int(rays.size()) / 5);  // the comparison must not be vacuous
}

void expect_matches_brute_force(const Scene& s, const WideBvh& bvh, const std::vector<Ray>& rays,
                                std::initializer_list<KernelBuild> builds) {
  for (KernelBuild build : builds) {
    SCOPED_TRACE("build options: " + build_options(build));
    // A tree deeper than the small stack is not a build that kernel can trace.
    if (build == KernelBuild::SmallStack || build == KernelBuild::PortableLanes) ASSERT_LT(bvh.height, kSmallStackSize);
    expect_outcomes(rays, run_compare(s, bvh, rays, build));
  }
}

}  // namespace caustica::test
