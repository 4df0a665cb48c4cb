// Grazing and tangent rays (issue 14) on one primitive at a time, at the
// origin and 1e5 away, under both builds of the primitive tests:
//   spheres: exactly tangent rays (either answer, finite), rays passing
//     2e-2 of the radius inside (hit) and outside (miss) the silhouette;
//   cylinders: rays along the axis (cap hits), axis-parallel rays just
//     inside / exactly on / just outside the side, rays in the caps' planes
//     just inside / on / outside the rims, perpendicular rays through the
//     side;
//   triangles: rays in the triangle's plane (miss), nearly in-plane rays
//     (hit), rays along an edge's line in the plane (miss).
// Every answer is finite (t, u, v); decisive cases must hit or miss as
// stated, with t within a relative 1e-4 (plus the position's rounding).
// Found: all hold (the cylinder test re-solves from the point nearest the
// axis and skips caps for rays parallel to them, which keeps t finite).
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <map>

#include "host/scene/scene.h"
#include "tests/stiff/stiff_support.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::vec3;
using test::runtime;

enum Expect { Hit_, Miss, Either };
struct Probe {
  vec3 o, d;
  Expect expect;
  float t;  // expected t for a hit (0: not checked)
  const char* what;
};

using stiff::upload_read_only;

class Grazing : public ::testing::TestWithParam<const char*> {
 protected:
  void run(uint32_t type, const Sphere& sp, const Cylinder& cy, const Triangle& tr, const std::vector<Probe>& probes,
           vec3 offset) {
    static auto& programs = *new std::map<std::string, cl::Program>;  // never released (test::runtime() says why)
    cl::Program& program = programs[GetParam()];
    if (!program())
      program = test::build_test_kernel("stiff/grazing.cl",
                                        std::string("-DHAS_SPHERES -DHAS_CYLINDERS -DHAS_TRIANGLES ") + GetParam())
                    .program;
    std::vector<cs_float4> rays;
    for (const Probe& p : probes) {
      rays.push_back(to_float4(p.o));
      rays.push_back(to_float4(p.d));
    }
    std::vector<cl::Buffer> keep = {upload_read_only(rays), upload_read_only(std::vector<Sphere>{sp}),
                                    upload_read_only(std::vector<Cylinder>{cy}), upload_read_only(std::vector<Triangle>{tr})};
    cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, probes.size() * sizeof(cs_float4));
    cl::Kernel k(program, "probe");
    k.setArg(0, keep[0]);
    k.setArg(1, cl_uint(probes.size()));
    for (int a = 0; a < 3; ++a) k.setArg(2 + a, keep[1 + a]);
    k.setArg(5, cl_uint(type << PRIM_TYPE_SHIFT));
    k.setArg(6, out);
    runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(probes.size(), 64)), cl::NDRange(64));
    std::vector<cs_float4> r(probes.size());
    runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, r.size() * sizeof(cs_float4), r.data());
    for (size_t i = 0; i < probes.size(); ++i) {
      const Probe& p = probes[i];
      uint32_t prim;
      std::memcpy(&prim, &r[i].w, 4);
      const bool hit = prim != PRIM_NONE;
      const std::string where = std::string(p.what) + " at offset " + std::to_string(offset.x);
      EXPECT_TRUE(std::isfinite(r[i].x) && std::isfinite(r[i].y) && std::isfinite(r[i].z)) << where;
      if (p.expect == Hit_) EXPECT_TRUE(hit) << where;
      if (p.expect == Miss) EXPECT_FALSE(hit) << where;
      if (hit && p.t > 0.0f && p.expect != Miss)
        EXPECT_NEAR(r[i].x, p.t, 1e-4f * p.t + 4e-7f * glm::length(offset)) << where;
    }
  }
};

TEST_P(Grazing, Spheres) {
  for (vec3 c : {vec3(0.0f), vec3(1e5f, -1e5f, 1e5f)}) {
    const Sphere sp{to_float4(c, 1.0f), 0, 0, 0, 0};
    std::vector<Probe> p;
    const vec3 dirs[] = {vec3(1, 0, 0), glm::normalize(vec3(1, 0, 1)), vec3(0, 0, -1)};
    for (const vec3& d : dirs) {
      const vec3 side = glm::normalize(glm::cross(d, vec3(0.3f, 1.0f, 0.2f)));
      p.push_back({c + side - 5.0f * d, d, Either, 0.0f, "tangent"});  // t of a tangent hit is good to sqrt(eps) only
      p.push_back({c + 0.98f * side - 5.0f * d, d, Hit_, 5.0f - std::sqrt(1.0f - 0.98f * 0.98f), "inside silhouette"});
      p.push_back({c + 1.02f * side - 5.0f * d, d, Miss, 0.0f, "outside silhouette"});
      p.push_back({c + side, d, Either, 0.0f, "from the tangent point along the tangent"});
    }
    run(PRIM_SPHERE, sp, Cylinder{}, Triangle{}, p, c);
  }
}

TEST_P(Grazing, Cylinders) {
  for (vec3 c : {vec3(0.0f), vec3(1e5f, -1e5f, 1e5f)}) {
    const Cylinder cy{to_float4(c, 1.0f), to_float4(vec3(0, 1, 0), 1.0f), 0, 0, 0, 0};
    const vec3 up(0, 1, 0), x(1, 0, 0), z(0, 0, 1);
    std::vector<Probe> p = {
        {c - 5.0f * up, up, Hit_, 4.0f, "along the axis"},
        {c + 5.0f * up, -up, Hit_, 4.0f, "along the axis, downward"},
        {c + 0.5f * x - 5.0f * up, up, Hit_, 4.0f, "axis-parallel inside"},
        {c + 0.98f * x - 5.0f * up, up, Hit_, 4.0f, "axis-parallel just inside the side"},
        {c + x - 5.0f * up, up, Either, 0.0f, "axis-parallel on the side"},
        {c + 1.02f * x - 5.0f * up, up, Miss, 0.0f, "axis-parallel just outside the side"},
        {c + x, up, Either, 0.0f, "axis-parallel from a side point"},
        {c - 5.0f * x + 0.98f * up, x, Hit_, 4.0f, "in a plane just below the top cap"},
        {c - 5.0f * x + up, x, Either, 4.0f, "in the top cap's plane"},
        {c - 5.0f * x + 1.02f * up, x, Miss, 0.0f, "just above the top cap"},
        {c - 5.0f * x + z, x, Either, 0.0f, "tangent to the side"},
        {c - 5.0f * x + 0.98f * z, x, Hit_, 5.0f - std::sqrt(1.0f - 0.98f * 0.98f), "inside the side's silhouette"},
        {c - 5.0f * x + 1.02f * z, x, Miss, 0.0f, "outside the side's silhouette"},
        {c - 5.0f * x - 5.0f * up, glm::normalize(x + up), Either, 0.0f, "through the rim edge"},
        {c, up, Hit_, 1.0f, "from the centre along the axis"},
        {c, x, Hit_, 1.0f, "from the centre across the axis"},
    };
    run(PRIM_CYLINDER, Sphere{}, cy, Triangle{}, p, c);
  }
}

TEST_P(Grazing, Triangles) {
  for (vec3 c : {vec3(0.0f), vec3(1e5f, -1e5f, 1e5f)}) {
    const Triangle tr{to_float4(c), to_float4(c + vec3(1, 0, 0)), to_float4(c + vec3(0, 1, 0)), 0, 0, 0, 0};
    std::vector<Probe> p = {
        {c + vec3(-1, 0.25f, 0), vec3(1, 0, 0), Miss, 0.0f, "in the plane"},
        {c + vec3(-1, -1, 0), glm::normalize(vec3(1, 1, 0)), Miss, 0.0f, "in the plane through a vertex"},
        {c + vec3(-1, 0, 0), vec3(1, 0, 0), Miss, 0.0f, "along an edge's line"},
        {c + vec3(0.25f, 0.25f, 0), vec3(1, 0, 0), Miss, 0.0f, "in the plane from inside"},
        // 0.05 above the plane: still 6 float spacings at 1e5.
        {c + vec3(-1, 0.25f, 5e-2f), glm::normalize(vec3(1.25f, 0, -5e-2f)), Hit_, 0.0f, "nearly in the plane"},
        {c + vec3(0.25f, 0.25f, 1), vec3(0, 0, -1), Hit_, 1.0f, "head on"},
    };
    run(PRIM_TRIANGLE, Sphere{}, Cylinder{}, tr, p, c);
  }
}

INSTANTIATE_TEST_SUITE_P(BuildOptions, Grazing, ::testing::Values("", "-cl-fast-relaxed-math"),
                         [](const auto& info) { return info.index == 0 ? std::string("Strict") : std::string("FastMath"); });

}  // namespace
}  // namespace caustica
