// Texture coordinates and shading normals from surface_at, texture_lookup's
// bilinear wrap-around sampling and checkers (kernel level, hand-computed
// answers), and the host side: sRGB decoding, every supported image format
// read back from files written here, the missing-file fallback, loading each
// file once, and finding textures whose written paths came from elsewhere.
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
#include <map>

#include "host/scene/scene.h"
#include "host/scene/textures.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

namespace fs = std::filesystem;
using glm::vec2;
using glm::vec3;
using test::runtime;

const float kPi = 3.14159265358979f;

template <class T>
cl::Buffer upload(std::vector<T> v) {
  if (v.empty()) v.resize(1);  // OpenCL refuses zero-sized buffers
  return cl::Buffer(runtime().context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T), v.data());
}

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
float from_bits(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// One surface_at query: the hit and the ray it was found along.
struct Query {
  uint32_t type;
  uint32_t index;
  float t, u, v;
  vec3 o, d{0.0f, 0.0f, 1.0f};
};

struct Surface {
  vec3 position, normal, shading_normal;
  vec2 uv;
};

class Textures : public ::testing::TestWithParam<const char*> {
 protected:
  // tests/kernels/<file> built with `options` and the parameter's.
  cl::Program program(const char* file, const std::string& options) {
    static auto& programs = *new std::map<std::string, cl::Program>;  // never released (test::runtime() says why)
    const std::string all = options + " " + GetParam();
    auto& p = programs[std::string(file) + all];
    if (!p()) p = test::build_test_kernel(file, all).program;
    return p;
  }

  std::vector<Surface> surface(const Scene& s, const std::vector<Query>& queries, bool with_shading) {
    // Texture coordinates of spheres and cylinders exist only with textures.
    std::string options = "-DHAS_SPHERES -DHAS_CYLINDERS -DHAS_TRIANGLES -DHAS_TEXTURES";
    if (with_shading) options += " -DHAS_TRIANGLE_SHADING";
    cl::Kernel k(program("textures_surface.cl", options), "surface");
    std::vector<cs_float4> hits, origins, dirs;
    for (const Query& q : queries) {
      hits.push_back(cs_float4{q.t, q.u, q.v, from_bits(q.type << PRIM_TYPE_SHIFT | q.index)});
      origins.push_back(to_float4(q.o));
      dirs.push_back(to_float4(q.d));
    }
    const size_t n = queries.size();
    cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, n * 4 * sizeof(cs_float4));
    std::vector<cl::Buffer> keep = {upload(hits),        upload(origins),     upload(dirs),
                                    upload(s.spheres),   upload(s.cylinders), upload(s.triangles),
                                    upload(s.triangle_shading)};
    k.setArg(0, keep[0]);
    k.setArg(1, keep[1]);
    k.setArg(2, keep[2]);
    k.setArg(3, static_cast<cl_uint>(n));
    for (int a = 4; a < 8; ++a) k.setArg(a, keep[a - 1]);
    k.setArg(8, out);
    runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
    std::vector<cs_float4> o(n * 4);
    runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, o.size() * sizeof(cs_float4), o.data());
    std::vector<Surface> result(n);
    for (size_t i = 0; i < n; ++i)
      result[i] = Surface{to_vec3(o[4 * i]), to_vec3(o[4 * i + 1]), to_vec3(o[4 * i + 2]),
                          vec2(o[4 * i + 3].x, o[4 * i + 3].y)};
    return result;
  }

  std::vector<vec3> sample(const Scene& s, const std::vector<std::pair<int, vec2>>& lookups) {
    cl::Kernel k(program("textures_sample.cl", "-DHAS_TEXTURES"), "sample");
    std::vector<int> index;
    std::vector<float> uv;
    for (const auto& l : lookups) {
      index.push_back(l.first);
      uv.push_back(l.second.x);
      uv.push_back(l.second.y);
    }
    const size_t n = lookups.size();
    cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, n * sizeof(cs_float4));
    std::vector<cl::Buffer> keep = {upload(s.textures), upload(s.texels), upload(index), upload(uv)};
    for (int a = 0; a < 4; ++a) k.setArg(a, keep[a]);
    k.setArg(4, static_cast<cl_uint>(n));
    k.setArg(5, out);
    runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
    std::vector<cs_float4> o(n);
    runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, o.size() * sizeof(cs_float4), o.data());
    std::vector<vec3> result;
    for (const auto& v : o) result.push_back(to_vec3(v));
    return result;
  }
};

// Distance on the circle of u (u = 0 and u = 1 are the same meridian).
float circular(float a, float b) {
  const float d = std::abs(a - b);
  return std::min(d, 1.0f - d);
}

std::string str(vec3 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

TEST_P(Textures, SphereUvFollowsLongitudeAndLatitude) {
  Scene s;
  const vec3 c(1, 2, 3);
  const float r = 2.0f;
  s.spheres = {Sphere{to_float4(c, r), 0, 0, 0, 0}, Sphere{to_float4(vec3(0), 1.0f), 0, 0, 0, 0}};
  struct Case {
    float lon_deg, lat_deg, u, v;
  };
  // u = 0 toward +x, 0.25 toward +z; v = 0 at -y, 1 at +y.
  const Case cases[] = {
      {0, 0, 0.0f, 0.5f},          {90, 0, 0.25f, 0.5f},       {180, 0, 0.5f, 0.5f},
      {270, 0, 0.75f, 0.5f},       {45, 30, 0.125f, 2.0f / 3}, {200, -60, 200.0f / 360, 1.0f / 6},
      {200, 89.9f, 200.0f / 360, (90 + 89.9f) / 180},          {0.01f, 10, 0.01f / 360, 100.0f / 180},
      {-0.01f, 10, 1 - 0.01f / 360, 100.0f / 180},  // just across the seam
      {-1e-5f, 0, 1 - 1e-5f / 360, 0.5f},          // so close it may round to u = 1: must wrap to 0
  };
  std::vector<Query> q;
  for (const Case& k : cases) {
    const float lon = k.lon_deg * kPi / 180, lat = k.lat_deg * kPi / 180;
    const vec3 n(std::cos(lat) * std::cos(lon), std::sin(lat), std::cos(lat) * std::sin(lon));
    // Reached along a ray, t != 0: the uv must come from the hit, not from o.
    q.push_back({PRIM_SPHERE, 0, 3.0f, 0, 0, c + 5.0f * n, -n});
  }
  q.push_back({PRIM_SPHERE, 0, 0.0f, 0, 0, c + vec3(0, r, 0)});   // north pole
  q.push_back({PRIM_SPHERE, 0, 0.0f, 0, 0, c + vec3(0, -r, 0)});  // south pole
  // atan2 = -1e-9: 1 - 1.6e-10 rounds to exactly 1 in float.
  q.push_back({PRIM_SPHERE, 1, 0.0f, 0, 0, vec3(1, 0, -1e-9f)});
  const auto p = surface(s, q, false);
  for (size_t i = 0; i < std::size(cases); ++i) {
    EXPECT_GE(p[i].uv.x, 0.0f) << i;
    EXPECT_LT(p[i].uv.x, 1.0f) << i;
    EXPECT_LT(circular(p[i].uv.x, cases[i].u), 2e-5f) << i << ": u " << p[i].uv.x << " expected " << cases[i].u;
    EXPECT_NEAR(p[i].uv.y, cases[i].v, 2e-5f) << i;
    EXPECT_EQ(p[i].shading_normal, p[i].normal) << i;
  }
  const size_t north = std::size(cases), south = north + 1;
  EXPECT_NEAR(p[north].uv.y, 1.0f, 1e-6f);
  EXPECT_NEAR(p[south].uv.y, 0.0f, 1e-6f);
  EXPECT_EQ(p[north].uv.x, 0.0f);
  EXPECT_EQ(p[south].uv.x, 0.0f);
  EXPECT_LT(p[south + 1].uv.x, 1.0f);
  EXPECT_LT(circular(p[south + 1].uv.x, 0.0f), 1e-6f);
}

// The frame of cylinder_uv_frame, computed independently.
void cylinder_frame(vec3 a, vec3& t1, vec3& t2) {
  const vec3 m = glm::abs(a);
  const vec3 e = (m.x <= m.y && m.x <= m.z) ? vec3(1, 0, 0) : (m.y <= m.z ? vec3(0, 1, 0) : vec3(0, 0, 1));
  t1 = glm::normalize(glm::cross(a, e));
  t2 = glm::cross(a, t1);
}

TEST_P(Textures, CylinderUvOnSideAndCaps) {
  Scene s;
  const vec3 c(0.5f, -1, 2), a = glm::normalize(vec3(1, 2, 2));
  const float r = 0.75f, h = 1.5f;
  s.cylinders = {Cylinder{to_float4(c, r), to_float4(a, h), 0, 0, 0, 0},
                 Cylinder{to_float4(vec3(0), 1.0f), to_float4(vec3(0, 1, 0), 2.0f), 0, 0, 0, 0}};
  vec3 t1, t2;
  cylinder_frame(a, t1, t2);
  struct Side {
    float angle_deg, z;
  };
  const Side sides[] = {{0, 0}, {90, 0.5f * h}, {180, h}, {270, -h}, {30, -0.25f * h}, {359.9f, 0.9f * h}};
  std::vector<Query> q;
  for (const Side& k : sides) {
    const float th = k.angle_deg * kPi / 180;
    const vec3 radial = std::cos(th) * t1 + std::sin(th) * t2;
    q.push_back({PRIM_CYLINDER, 0, 2.0f, CYL_PART_SIDE, k.z, c + k.z * a + (r + 2.0f) * radial, -radial});
  }
  // Caps: centre, along t1, along t2, and a diagonal point, on both caps.
  const vec3 top = c + h * a, bottom = c - h * a;
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_TOP, 0, top});
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_TOP, 0, top + r * t1});
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_TOP, 0, top + r * t2});
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_BOTTOM, 0, bottom});
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_BOTTOM, 0, bottom - r * t1});
  q.push_back({PRIM_CYLINDER, 0, 0.0f, CYL_PART_BOTTOM, 0, bottom + 0.5f * r * (t1 - t2)});
  // Vertical axis: e = x (tie with z goes to x), t1 = y x x = -z, t2 = -x,
  // hard-coded so that a wrong frame rule cannot hide behind the helper.
  q.push_back({PRIM_CYLINDER, 1, 0.0f, CYL_PART_SIDE, 0, vec3(0, 0, -1)});
  q.push_back({PRIM_CYLINDER, 1, 0.0f, CYL_PART_SIDE, 1, vec3(-1, 1, 0)});
  q.push_back({PRIM_CYLINDER, 1, 0.0f, CYL_PART_SIDE, 0, vec3(0, -2, 1)});
  q.push_back({PRIM_CYLINDER, 1, 0.0f, CYL_PART_SIDE, 0, vec3(1, 0, 0)});
  q.push_back({PRIM_CYLINDER, 1, 0.0f, CYL_PART_TOP, 0, vec3(0.5f, 2, 0)});
  const auto p = surface(s, q, false);
  size_t i = 0;
  for (const Side& k : sides) {
    EXPECT_LT(circular(p[i].uv.x, k.angle_deg / 360), 2e-5f) << "side " << i << ": u " << p[i].uv.x;
    EXPECT_LT(p[i].uv.x, 1.0f);
    EXPECT_NEAR(p[i].uv.y, (k.z + h) / (2 * h), 2e-5f) << "side " << i;
    ++i;
  }
  const vec2 caps[] = {{0.5f, 0.5f}, {1.0f, 0.5f}, {0.5f, 1.0f}, {0.5f, 0.5f}, {0.0f, 0.5f}, {0.75f, 0.25f}};
  for (const vec2& uv : caps) {
    EXPECT_NEAR(p[i].uv.x, uv.x, 2e-5f) << "cap " << i;
    EXPECT_NEAR(p[i].uv.y, uv.y, 2e-5f) << "cap " << i;
    ++i;
  }
  const vec2 vertical[] = {{0.0f, 0.5f}, {0.25f, 0.75f}, {0.5f, 0.0f}, {0.75f, 0.5f}, {0.5f, 0.25f}};
  for (const vec2& uv : vertical) {
    EXPECT_LT(circular(p[i].uv.x, uv.x), 2e-5f) << "vertical " << i << ": u " << p[i].uv.x;
    EXPECT_NEAR(p[i].uv.y, uv.y, 2e-5f) << "vertical " << i;
    EXPECT_EQ(p[i].shading_normal, p[i].normal) << i;
    ++i;
  }
}

Triangle make_triangle(vec3 a, vec3 b, vec3 c) {
  return Triangle{to_float4(a), to_float4(b), to_float4(c), 0, 0, 0, 0};
}

TEST_P(Textures, TriangleUvDefaultsWithoutShadingTable) {
  Scene s;
  s.triangles = {make_triangle(vec3(1, 1, 1), vec3(3, 1, 1), vec3(1, 4, 1))};
  const auto p = surface(s,
                         {{PRIM_TRIANGLE, 0, 0, 0.25f, 0.5f, vec3(0)},
                          {PRIM_TRIANGLE, 0, 0, 0, 0, vec3(0)},
                          {PRIM_TRIANGLE, 0, 0, 1, 0, vec3(0)},
                          {PRIM_TRIANGLE, 0, 0, 0, 1, vec3(0)}},
                         false);
  const vec2 expected[] = {{0.25f, 0.5f}, {0, 0}, {1, 0}, {0, 1}};
  // Exact under IEEE rounding; -cl-fast-relaxed-math may normalise with an
  // approximate rsqrt (NVIDIA's gives 1 - 2^-24).
  const float tolerance = std::string(GetParam()).find("fast-relaxed") != std::string::npos ? 4e-7f : 0.0f;
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(p[i].uv, expected[i]) << i;
    EXPECT_LE(glm::length(p[i].shading_normal - vec3(0, 0, 1)), tolerance) << i;
    EXPECT_LE(glm::length(p[i].normal - vec3(0, 0, 1)), tolerance) << i;
  }
  EXPECT_LT(glm::length(p[0].position - vec3(1.5f, 2.5f, 1)), 1e-6f);
}

TEST_P(Textures, TriangleUvAndShadingNormalInterpolation) {
  Scene s;
  // Counter-clockwise seen from +z: geometric normal +z for all three.
  for (int k = 0; k < 3; ++k) s.triangles.push_back(make_triangle(vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 2, 0)));
  const vec3 n0 = glm::normalize(vec3(1, 0, 1)), n1 = glm::normalize(vec3(0, 1, 1)), n2(0, 0, 1);
  // Vertex normals on the far side of the winding (a mesh wound clockwise).
  const vec3 m0 = glm::normalize(vec3(0.3f, 0, -1)), m1 = glm::normalize(vec3(0, -0.2f, -1)), m2(0, 0, -1);
  s.triangle_shading = {
      TriangleShading{to_float4(n0), to_float4(n1), to_float4(n2), 0.1f, 0.2f, 0.9f, 0.3f, 0.4f, 1.7f, 0, 0},
      TriangleShading{to_float4(m0), to_float4(m1), to_float4(m2), 0, 0, 1, 0, 0, 1, 0, 0},
      // Opposite normals cancel halfway along the first edge.
      TriangleShading{to_float4(vec3(1, 0, 0)), to_float4(vec3(-1, 0, 0)), to_float4(n2), 0, 0, 1, 0, 0, 1, 0, 0}};
  const float u = 0.2f, v = 0.3f, w = 1 - u - v;
  const auto p = surface(s,
                         {{PRIM_TRIANGLE, 0, 0, u, v, vec3(0)},
                          {PRIM_TRIANGLE, 0, 0, 0, 0, vec3(0)},
                          {PRIM_TRIANGLE, 1, 0, u, v, vec3(0)},
                          {PRIM_TRIANGLE, 2, 0, 0.5f, 0, vec3(0)}},
                         true);
  EXPECT_NEAR(p[0].uv.x, w * 0.1f + u * 0.9f + v * 0.4f, 1e-6f);  // 0.35
  EXPECT_NEAR(p[0].uv.y, w * 0.2f + u * 0.3f + v * 1.7f, 1e-6f);  // 0.67
  const vec3 expected = glm::normalize(w * n0 + u * n1 + v * n2);
  EXPECT_LT(glm::length(p[0].shading_normal - expected), 1e-6f) << str(p[0].shading_normal);
  EXPECT_EQ(p[0].normal, vec3(0, 0, 1));
  EXPECT_NEAR(p[1].uv.x, 0.1f, 1e-7f);
  EXPECT_NEAR(p[1].uv.y, 0.2f, 1e-7f);
  EXPECT_LT(glm::length(p[1].shading_normal - n0), 1e-6f);
  const vec3 flipped = -glm::normalize(w * m0 + u * m1 + v * m2);
  EXPECT_LT(glm::length(p[2].shading_normal - flipped), 1e-6f) << str(p[2].shading_normal);
  EXPECT_GT(p[2].shading_normal.z, 0.0f);
  EXPECT_EQ(p[3].shading_normal, vec3(0, 0, 1));
}

// A 3x2 image at texel offset 1 (behind a 1-texel image, so a lookup that
// ignores the offset reads wrong values), texel (column i, row j from the
// top) = (1 + i + 3 j, i / 2, j): rows top 1 2 3, bottom 4 5 6 in red.
Scene sampling_scene() {
  Scene s;
  auto push = [&](vec3 c) {
    for (float x : {c.x, c.y, c.z, 1.0f}) s.texels.push_back(glm::packHalf1x16(x));
  };
  push(vec3(7, 8, 9));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) push(vec3(1 + i + 3 * j, 0.5f * i, j));
  auto image = [](uint32_t offset, uint32_t w, uint32_t h) {
    Texture t{};
    t.kind = TEXTURE_IMAGE;
    t.offset = offset, t.width = w, t.height = h;
    return t;
  };
  s.textures = {image(0, 1, 1), image(1, 3, 2)};
  Texture checker{};
  checker.kind = TEXTURE_CHECKER;
  checker.color1 = to_float4(vec3(1, 0, 0));
  checker.color2 = to_float4(vec3(0, 0, 1));
  checker.scale = 4.0f;
  s.textures.push_back(checker);
  return s;
}

vec3 texel(int i, int j) { return vec3(1 + i + 3 * j, 0.5f * i, j); }

TEST_P(Textures, BilinearSamplingWrapsAroundTheBorders) {
  const Scene s = sampling_scene();
  struct Case {
    vec2 uv;
    vec3 expected;
    const char* what;
  };
  const float c0 = 1.0f / 6, c1 = 0.5f, c2 = 5.0f / 6;  // column centres
  const float top = 0.75f, bottom = 0.25f;             // row centres: v = 0 is the bottom
  const Case cases[] = {
      {{c0, top}, texel(0, 0), "top-left centre"},
      {{c2, bottom}, texel(2, 1), "bottom-right centre"},
      {{c1, bottom}, texel(1, 1), "bottom-middle centre"},
      {{1.0f / 3, top}, 0.5f * (texel(0, 0) + texel(1, 0)), "between columns 0 and 1"},
      {{c0 + 1.0f / 12, top}, 0.75f * texel(0, 0) + 0.25f * texel(1, 0), "a quarter toward column 1"},
      {{c1, 0.5f}, 0.5f * (texel(1, 0) + texel(1, 1)), "between the rows"},
      {{1.0f / 3, 0.5f}, 0.25f * (texel(0, 0) + texel(1, 0) + texel(0, 1) + texel(1, 1)), "between four"},
      {{c1, 0.625f}, 0.75f * texel(1, 0) + 0.25f * texel(1, 1), "a quarter toward the bottom row"},
      {{0.0f, top}, 0.5f * (texel(2, 0) + texel(0, 0)), "u = 0: across the left/right border"},
      {{1.0f, top}, 0.5f * (texel(2, 0) + texel(0, 0)), "u = 1: the same"},
      {{c0, 0.0f}, 0.5f * (texel(0, 1) + texel(0, 0)), "v = 0: across the bottom/top border"},
      {{c0, 1.0f}, 0.5f * (texel(0, 1) + texel(0, 0)), "v = 1: the same"},
      {{0.0f, 0.0f}, 0.25f * (texel(2, 1) + texel(0, 1) + texel(2, 0) + texel(0, 0)), "the corner"},
      {{1.0f / 24, top}, 0.375f * texel(2, 0) + 0.625f * texel(0, 0), "inside the left half-texel"},
      {{c0 - 2.0f, top - 3.0f}, texel(0, 0), "negative uv"},
      {{c2 + 7.0f, bottom + 12.0f}, texel(2, 1), "uv > 1"},
      {{-1e-9f, top}, 0.5f * (texel(2, 0) + texel(0, 0)), "tiny negative u (rounds to 1)"},
      {{1e30f, top}, 0.5f * (texel(2, 0) + texel(0, 0)), "huge u (an integer)"},
      {{-1e30f, -1e30f}, 0.25f * (texel(2, 1) + texel(0, 1) + texel(2, 0) + texel(0, 0)), "huge negative uv"},
  };
  std::vector<std::pair<int, vec2>> lookups;
  for (const Case& k : cases) lookups.push_back({1, k.uv});
  lookups.push_back({0, {0.3f, 0.9f}});   // 1x1: every lookup is its one texel
  lookups.push_back({0, {-2.5f, 0.0f}});
  const auto p = sample(s, lookups);
  for (size_t i = 0; i < std::size(cases); ++i)
    EXPECT_LT(glm::length(p[i] - cases[i].expected), 2e-4f)
        << cases[i].what << ": got " << str(p[i]) << " expected " << str(cases[i].expected);
  EXPECT_EQ(p[std::size(cases)], vec3(7, 8, 9));
  EXPECT_EQ(p[std::size(cases) + 1], vec3(7, 8, 9));
}

// Wrap modes, the nearest-texel filter and the affine uv map (glTF's
// sampler and KHR_texture_transform; lib/texture.h), on the same 3x2 image.
TEST_P(Textures, WrapModesNearestFilterAndUvTransform) {
  Scene s = sampling_scene();
  auto with = [&](cs_uint sampling, vec3 uv_u = vec3(1, 0, 0), vec3 uv_v = vec3(0, 1, 0)) {
    Texture t = s.textures[1];
    t.sampling = sampling;
    t.uv_u = to_float4(uv_u);
    t.uv_v = to_float4(uv_v);
    s.textures.push_back(t);
    return int(s.textures.size() - 1);
  };
  const int clamp = with(TEXTURE_CLAMP_U | TEXTURE_CLAMP_V), mirror = with(TEXTURE_MIRROR_U | TEXTURE_MIRROR_V);
  const int nearest = with(TEXTURE_NEAREST);
  const int swapped = with(TEXTURE_TRANSFORMED, vec3(0, 1, 0), vec3(1, 0, 0));       // u' = v, v' = u
  const int shifted = with(TEXTURE_TRANSFORMED, vec3(1, 0, 1.0f / 3), vec3(0, 1, 0));  // u' = u + 1/3
  const int shifted_clamped = with(TEXTURE_TRANSFORMED | TEXTURE_CLAMP_U, vec3(1, 0, 1.0f / 3), vec3(0, 1, 0));
  const float c0 = 1.0f / 6, c1 = 0.5f, c2 = 5.0f / 6, top = 0.75f, bottom = 0.25f;
  struct Case {
    int texture;
    vec2 uv;
    vec3 expected;
    const char* what;
  };
  const Case cases[] = {
      {clamp, {-0.5f, top}, texel(0, 0), "clamp: left of the image reads the left column"},
      {clamp, {1.5f, top}, texel(2, 0), "clamp: right of it, the right column"},
      {clamp, {0.0f, top}, texel(0, 0), "clamp: u = 0 does not reach across to the right column"},
      {clamp, {c1, -0.3f}, texel(1, 1), "clamp: below the image, the bottom row"},
      {clamp, {c1, 7.0f}, texel(1, 0), "clamp: above it, the top row"},
      {clamp, {c0, 0.5f}, 0.5f * (texel(0, 0) + texel(0, 1)), "clamp: inside, bilinear as ever"},
      {mirror, {-c0, top}, texel(0, 0), "mirror: -1/6 is 1/6"},
      {mirror, {1.0f + c0, top}, texel(2, 0), "mirror: 7/6 is 5/6"},
      {mirror, {2.0f + c0, top}, texel(0, 0), "mirror: period 2"},
      {mirror, {1.0f, top}, texel(2, 0), "mirror: the right edge meets its mirror image"},
      {mirror, {c1, -bottom}, texel(1, 1), "mirror in v"},
      {nearest, {1.0f / 3 - 0.01f, top}, texel(0, 0), "nearest: just left of the column border"},
      {nearest, {1.0f / 3 + 0.01f, top}, texel(1, 0), "nearest: just right of it"},
      {nearest, {0.999f, 0.001f}, texel(2, 1), "nearest: the bottom-right corner"},
      {nearest, {1.001f, top}, texel(0, 0), "nearest: repeat past u = 1"},
      {swapped, {top, c0}, texel(0, 0), "transform: uv swapped"},
      {swapped, {bottom, c2}, texel(2, 1), "transform: uv swapped, the other corner"},
      {shifted, {c0, top}, texel(1, 0), "transform: u + 1/3 moves one column right"},
      {shifted, {c2, top}, texel(0, 0), "transform: and wraps"},
      {shifted_clamped, {c2, top}, texel(2, 0), "transform, then clamp"},
  };
  std::vector<std::pair<int, vec2>> lookups;
  for (const Case& k : cases) lookups.push_back({k.texture, k.uv});
  const auto p = sample(s, lookups);
  for (size_t i = 0; i < std::size(cases); ++i)
    EXPECT_LT(glm::length(p[i] - cases[i].expected), 2e-4f)
        << cases[i].what << ": got " << str(p[i]) << " expected " << str(cases[i].expected);
}

TEST_P(Textures, CheckerPattern) {
  const Scene s = sampling_scene();
  const vec3 even(1, 0, 0), odd(0, 0, 1);
  struct Case {
    vec2 uv;
    vec3 expected;
  };
  // scale 4: squares 0.25 wide.
  const Case cases[] = {{{0.1f, 0.1f}, even},   {{0.3f, 0.1f}, odd},    {{0.3f, 0.3f}, even},
                        {{0.1f, 0.3f}, odd},    {{-0.1f, 0.1f}, odd},   {{-0.1f, -0.1f}, even},
                        {{2.6f, 0.1f}, even},   {{2.6f, 0.35f}, odd},   {{-2.6f, 0.1f}, odd},
                        {{0.0f, 0.0f}, even},   {{0.25f, 0.0f}, odd}};
  std::vector<std::pair<int, vec2>> lookups;
  for (const Case& k : cases) lookups.push_back({2, k.uv});
  lookups.push_back({2, {1e30f, -1e30f}});
  const auto p = sample(s, lookups);
  for (size_t i = 0; i < std::size(cases); ++i)
    EXPECT_EQ(p[i], cases[i].expected) << "uv " << cases[i].uv.x << ", " << cases[i].uv.y;
  const vec3 huge = p[std::size(cases)];
  EXPECT_TRUE(huge == even || huge == odd) << str(huge);
}

// The body is guarded by HAS_TEXTURES: without it nothing is defined, so a
// program may define the same names itself.
TEST_P(Textures, LookupCompiledOnlyWithTheFlag) {
  EXPECT_NO_THROW(test::build_test_kernel("textures_guard.cl", GetParam()));
}

INSTANTIATE_TEST_SUITE_P(BuildOptions, Textures, ::testing::Values("", "-cl-fast-relaxed-math"),
                         [](const auto& info) { return info.index == 0 ? std::string("Strict") : std::string("FastMath"); });

// ---------------------------------------------------------------- host side

TEST(TextureHost, SrgbDecode) {
  EXPECT_EQ(srgb_byte_to_linear(0), 0.0f);
  EXPECT_EQ(srgb_byte_to_linear(255), 1.0f);
  EXPECT_NEAR(srgb_byte_to_linear(188), 0.50289f, 2e-5f);
  EXPECT_NEAR(srgb_byte_to_linear(10), 10.0f / 255 / 12.92f, 1e-7f);  // linear segment
  EXPECT_NEAR(srgb_byte_to_linear(128), 0.21586f, 2e-5f);
  for (int i = 1; i < 256; ++i) EXPECT_GT(srgb_byte_to_linear(i), srgb_byte_to_linear(i - 1)) << i;
}

float half_at(const Scene& s, size_t texel, int channel) {
  return glm::unpackHalf1x16(s.texels[texel * 4 + channel]);
}

// Texels of texture `index` equal `expected` (linear rgb, row-major from
// the top), and their fourth channel the image's alpha (1 where it has none).
void expect_texels(const Scene& s, int index, int w, int h, const std::vector<vec3>& expected, float tol,
                   const std::string& what, const std::vector<float>& alpha = {}) {
  ASSERT_GE(index, 0) << what;
  ASSERT_LT(static_cast<size_t>(index), s.textures.size()) << what;
  const Texture& t = s.textures[index];
  ASSERT_EQ(t.kind, TEXTURE_IMAGE) << what;
  ASSERT_EQ(t.width, static_cast<cs_uint>(w)) << what;
  ASSERT_EQ(t.height, static_cast<cs_uint>(h)) << what;
  ASSERT_LE((t.offset + static_cast<size_t>(w) * h) * 4, s.texels.size()) << what;
  for (int k = 0; k < w * h; ++k) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(half_at(s, t.offset + k, c), expected[k][c], tol + 1e-3f * expected[k][c])
          << what << " texel " << k << " channel " << c;
    if (alpha.empty())
      EXPECT_EQ(half_at(s, t.offset + k, 3), 1.0f) << what;
    else
      EXPECT_NEAR(half_at(s, t.offset + k, 3), alpha[size_t(k)], 1e-3f) << what << " texel " << k << " alpha";
  }
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// 2x2, top row: black, white; bottom row: (188, 10, 128), (50, 100, 200).
const unsigned char kPixels[] = {0, 0, 0, 255, 255, 255, 188, 10, 128, 50, 100, 200};

std::vector<vec3> decoded(const unsigned char* rgb, int count) {
  std::vector<vec3> out;
  for (int i = 0; i < count; ++i)
    out.push_back(vec3(srgb_byte_to_linear(rgb[3 * i]), srgb_byte_to_linear(rgb[3 * i + 1]),
                       srgb_byte_to_linear(rgb[3 * i + 2])));
  return out;
}

TEST(TextureHost, LoadsEveryFormat) {
  const std::string dir = test::temp_dir();
  ASSERT_TRUE(stbi_write_png((dir + "/a.png").c_str(), 2, 2, 3, kPixels, 2 * 3));
  ASSERT_TRUE(stbi_write_bmp((dir + "/a.bmp").c_str(), 2, 2, 3, kPixels));
  ASSERT_TRUE(stbi_write_tga((dir + "/a.tga").c_str(), 2, 2, 3, kPixels));
  const unsigned char rgba[] = {188, 10, 128, 0, 50, 100, 200, 77};
  ASSERT_TRUE(stbi_write_png((dir + "/rgba.png").c_str(), 2, 1, 4, rgba, 2 * 4));
  const unsigned char grey[] = {188, 0, 255};
  ASSERT_TRUE(stbi_write_png((dir + "/grey.png").c_str(), 3, 1, 1, grey, 3));
  // Values RGBE stores exactly (powers of two sharing an exponent range).
  const float hdr[] = {2.0f, 0.5f, 0.25f, 0.125f, 1.0f, 4.0f};
  ASSERT_TRUE(stbi_write_hdr((dir + "/a.hdr").c_str(), 2, 1, 3, hdr));
  std::vector<unsigned char> flat(16 * 16 * 3, 188);
  ASSERT_TRUE(stbi_write_jpg((dir + "/a.jpg").c_str(), 16, 16, 3, flat.data(), 95));
  write_file(dir + "/a.ppm", "P6\n# written by test_textures\n2 2\n255\n" +
                                 std::string(reinterpret_cast<const char*>(kPixels), sizeof(kPixels)));
  write_file(dir + "/ascii.ppm", "P3\n# ascii\n2 2 255\n0 0 0  255 255 255\n188 10 128\n50 100 200\n");
  write_file(dir + "/maxval.ppm", "P3 1 1 15 15 0 7\n");
  write_file(dir + "/ascii.pgm", "P2\n3 1\n255\n188 0 255\n");
  write_file(dir + "/binary.pgm", "P5 3 1 255\n" + std::string(reinterpret_cast<const char*>(grey), 3));
  write_file(dir + "/wide.ppm", std::string("P6 1 1 65535\n") + char(0xFF) + char(0xFF) + char(0) + char(0) +
                                    char(0x80) + char(0x00));

  Scene s;
  TextureLibrary lib(s);
  std::vector<std::string> warnings;
  const auto load = [&](const std::string& name) { return lib.image(name, dir, "test: " + name, warnings); };
  const std::vector<vec3> expected = decoded(kPixels, 4);
  for (const char* name : {"a.png", "a.bmp", "a.tga", "a.ppm", "ascii.ppm"})
    expect_texels(s, load(name), 2, 2, expected, 1e-6f, name);
  expect_texels(s, load("rgba.png"), 2, 1, decoded(kPixels + 6, 2), 1e-6f, "rgba.png", {0.0f, 77 / 255.0f});
  const float g188 = srgb_byte_to_linear(188);
  const std::vector<vec3> greys = {vec3(g188), vec3(0), vec3(1)};
  expect_texels(s, load("grey.png"), 3, 1, greys, 1e-6f, "grey.png");
  expect_texels(s, load("ascii.pgm"), 3, 1, greys, 1e-6f, "ascii.pgm");
  expect_texels(s, load("binary.pgm"), 3, 1, greys, 1e-6f, "binary.pgm");
  // maxval 15: 7/15 through the sRGB curve, not 7/255.
  const float seven = static_cast<float>(std::pow((7.0 / 15 + 0.055) / 1.055, 2.4));
  expect_texels(s, load("maxval.ppm"), 1, 1, {vec3(1, 0, seven)}, 1e-6f, "maxval.ppm");
  const float half16 = static_cast<float>(std::pow((32768.0 / 65535 + 0.055) / 1.055, 2.4));
  expect_texels(s, load("wide.ppm"), 1, 1, {vec3(1, 0, half16)}, 1e-6f, "wide.ppm");
  expect_texels(s, load("a.hdr"), 2, 1, {vec3(2, 0.5f, 0.25f), vec3(0.125f, 1, 4)}, 1e-6f, "a.hdr (linear)");
  expect_texels(s, load("a.jpg"), 16, 16, std::vector<vec3>(256, vec3(g188)), 0.01f, "a.jpg");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  // Each image follows the previous one in the texel buffer.
  size_t next = 0;
  for (const Texture& t : s.textures) {
    EXPECT_EQ(t.offset, next);
    next += static_cast<size_t>(t.width) * t.height;
  }
  EXPECT_EQ(s.texels.size(), next * 4);
}

TEST(TextureHost, MissingOrUnreadableFileBecomesOneSharedChecker) {
  const std::string dir = test::temp_dir();
  write_file(dir + "/broken.png", "this is not a png");
  Scene s;
  TextureLibrary lib(s);
  std::vector<std::string> warnings;
  const int a = lib.image("/Users/someone/missing_texture.png", dir, "scene.json: /materials/2", warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("scene.json: /materials/2: "), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("\"/Users/someone/missing_texture.png\" not found"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find(dir + "/textures/missing_texture.png"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("magenta/black checker"), std::string::npos) << warnings[0];
  ASSERT_GE(a, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[a].kind, TEXTURE_CHECKER);
  EXPECT_EQ(to_vec3(s.textures[a].color1), vec3(1, 0, 1));
  EXPECT_EQ(to_vec3(s.textures[a].color2), vec3(0, 0, 0));
  EXPECT_GT(s.textures[a].scale, 0.0f);

  const int b = lib.image("broken.png", dir, "scene.json: /materials/3", warnings);
  EXPECT_EQ(b, a);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[1].find("\"broken.png\""), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[1].find("cannot be read"), std::string::npos) << warnings[1];
  // Every reference is reported, but the fallback exists once.
  EXPECT_EQ(lib.image("broken.png", dir, "scene.json: /materials/4", warnings), a);
  EXPECT_EQ(warnings.size(), 3u);
  EXPECT_EQ(s.textures.size(), 1u);
  EXPECT_TRUE(s.texels.empty());
}

// Sizes are checked on the header, before any pixel is allocated (issue 14:
// a 20-byte PPM declaring 16384 x 16384 was std::bad_alloc after 28 s).
TEST(TextureHost, OversizedOrTruncatedHeadersAreRefusedBeforeAllocation) {
  LinearImage img;
  const struct {
    std::string bytes;
    std::vector<std::string> parts;
  } cases[] = {
      {"P6\n16384 16384\n255\nx", {"16384 x 16384", "texture limit of 16384 per side and 134217728 pixels"}},
      {"P6\n1000000 1000000\n255\n", {"1000000 x 1000000", "texture limit"}},
      {"P3\n4000 4000\n255\n1 2 3\n", {"4000 x 4000", "pixels in a file of"}},
      {"P6\n64 64\n255\n" + std::string(100, 'x'), {"truncated PNM data", "needs 12288 bytes"}},
      {"P2\n2 2\n255\n1 2\n", {"truncated PNM data", "needs at least 7 bytes"}},
  };
  // Found by fuzz/fuzz_texture (a timeout): a 16 KB uncompressed TGA declaring
  // ~2^27 pixels, which stb fills from bytes past the end, 2 GB and 10 s later.
  std::string tga = std::string("\0\0\2\0\0\0\0\0\0\0\0\0", 12) + std::string("\x00\x20\x00\x20\x18\x00", 6) + std::string(100, '\x7f');
  const std::string tga_why = decode_texture_image(tga, img);
  EXPECT_TRUE(test::Contains(tga_why, {"8192 x 8192", "in a file of 118 bytes", "packs 256 pixels per byte"}));
  for (const auto& c : cases) {
    const std::string why = decode_texture_image(c.bytes, img);
    for (const auto& part : c.parts) EXPECT_TRUE(test::Contains(why, {part})) << c.bytes.substr(0, 20);
  }
  // Found by fuzz/fuzz_texture (an abort): a JPEG whose scan uses an AC
  // table it never defines; Debian's stb_image asserts on it.
  const unsigned char jpeg[] = {
      0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49, 0x46, 0x00, 0x01, 0x01, 0x00, 0x05, 0x34, 0x34, 0x34,
      0x01, 0x3d, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1e, 0xff, 0xc0, 0x00, 0x11, 0x08, 0x00, 0x31, 0x00,
      0x9b, 0x03, 0x01, 0x22, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01, 0xff, 0xc4, 0x00, 0x1a, 0x00, 0x00, 0x03,
      0x01, 0x01, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x09, 0x06, 0x02,
      0x03, 0x04, 0xc2, 0xff, 0xc4, 0x00, 0x17, 0x01, 0x01, 0x01, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x11, 0x12, 0x21, 0xff, 0xda, 0x00, 0x0c, 0x03, 0x01, 0x00, 0x02,
      0x11, 0x03, 0x11, 0x00, 0x3f, 0x00, 0xde, 0x10, 0x48, 0x63, 0x31, 0x4b, 0x30, 0xd7, 0xff, 0xd9};
  EXPECT_TRUE(test::Contains(decode_texture_image(std::string(reinterpret_cast<const char*>(jpeg), sizeof jpeg), img),
                             {"corrupt JPEG", "Huffman table"}));
  // Found by fuzz/fuzz_texture (a segfault in stb): fill bytes before the
  // start-of-image marker, which stb skips and the check above did not, and
  // a DC table symbol of 194, which stb uses unchecked as a mask index.
  std::ifstream filled_file(test::source_dir() + "/tests/data/textures/fuzz_jpeg_fill_bytes_dc_symbol.jpg",
                            std::ios::binary);
  const std::string filled((std::istreambuf_iterator<char>(filled_file)), std::istreambuf_iterator<char>());
  ASSERT_EQ(filled.size(), 120u);
  EXPECT_TRUE(test::Contains(decode_texture_image(filled, img),
                             {"corrupt JPEG: a DC Huffman table holds a symbol above 15"}));
  // A PNG header declaring 10^6 x 10^6 pixels: refused on the header.
  int w = 1, h = 1;
  std::string png;
  stbi_write_png_to_func([](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size); },
                         &png, w, h, 3, "\x10\x20\x30", 3);
  ASSERT_GT(png.size(), 24u);
  const unsigned char big[8] = {0x00, 0x0F, 0x42, 0x40, 0x00, 0x0F, 0x42, 0x40};  // 1000000, 1000000
  png.replace(16, 8, reinterpret_cast<const char*>(big), 8);
  EXPECT_TRUE(test::Contains(decode_texture_image(png, img), {"1000000 x 1000000", "texture limit"}));
}

TEST(TextureHost, SameFileIsLoadedOnce) {
  const std::string dir = test::temp_dir();
  fs::create_directories(dir + "/textures");
  ASSERT_TRUE(stbi_write_png((dir + "/textures/wood.png").c_str(), 2, 2, 3, kPixels, 6));
  Scene s;
  TextureLibrary lib(s);
  std::vector<std::string> warnings;
  const int a = lib.image("textures/wood.png", dir, "a", warnings);
  const int b = lib.image("./textures/../textures/wood.png", dir, "b", warnings);
  const int c = lib.image(dir + "/textures/wood.png", "/", "c", warnings);
  const int d = lib.image("C:\\Users\\someone\\wood.png", dir, "d", warnings);  // found by name
  // A link is the same file under another name.
  fs::create_symlink(dir + "/textures/wood.png", dir + "/link.png");
  const int e = lib.image("link.png", dir, "e", warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(a, b);
  EXPECT_EQ(a, c);
  EXPECT_EQ(a, d);
  EXPECT_EQ(a, e);
  EXPECT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.texels.size(), 2u * 2u * 4u);
  const int checker = lib.checker(vec3(0.2f), vec3(0.8f), 3.0f);
  EXPECT_EQ(checker, 1);
  EXPECT_EQ(s.textures[1].kind, TEXTURE_CHECKER);
  EXPECT_EQ(s.textures[1].scale, 3.0f);
  EXPECT_EQ(to_vec3(s.textures[1].color2), vec3(0.8f));
}

TEST(TextureHost, ResolvesPathsWrittenOnOtherMachines) {
  const std::string dir = test::temp_dir();
  fs::create_directories(dir + "/textures");
  fs::create_directories(dir + "/sub");
  for (const char* f : {"/textures/x.png", "/beside.png", "/sub/beside.png", "/both.png", "/textures/both.png"})
    write_file(dir + f, "x");
  const auto canon = [](const std::string& p) { return fs::weakly_canonical(p).string(); };
  // As written wins, then beside the scene, then <scene>/textures.
  EXPECT_EQ(resolve_texture_path("/Users/someone/proj/textures/x.png", dir), canon(dir + "/textures/x.png"));
  EXPECT_EQ(resolve_texture_path("C:\\Users\\someone\\proj\\x.png", dir), canon(dir + "/textures/x.png"));
  EXPECT_EQ(resolve_texture_path("textures\\x.png", dir), canon(dir + "/textures/x.png"));
  EXPECT_EQ(resolve_texture_path("sub/beside.png", dir), canon(dir + "/sub/beside.png"));
  EXPECT_EQ(resolve_texture_path("/elsewhere/beside.png", dir), canon(dir + "/beside.png"));
  EXPECT_EQ(resolve_texture_path("/elsewhere/both.png", dir), canon(dir + "/both.png"));
  EXPECT_EQ(resolve_texture_path(dir + "/sub/beside.png", "/nonexistent"), canon(dir + "/sub/beside.png"));
  EXPECT_EQ(resolve_texture_path("nothing.png", dir), "");
  EXPECT_EQ(resolve_texture_path("sub", dir), "");  // a folder is not a texture
  EXPECT_EQ(resolve_texture_path("", dir), "");
  // The repository's textures/ folder is searched too (CAUSTICA_TEXTURE_DIR).
  const auto candidates = texture_search_candidates("/Users/someone/x.png", dir);
  const std::string repo = fs::path(test::source_dir() + "/textures/x.png").lexically_normal().string();
  EXPECT_NE(std::find(candidates.begin(), candidates.end(), repo), candidates.end()) << repo;
  EXPECT_EQ(candidates.front(), "/Users/someone/x.png");
}

// Through the whole chain: a PNG whose top row is red and bottom row blue
// shows red at high v, blue at low v.
TEST(TextureHost, LoadedImageSampledInTheKernelIsUpright) {
  const std::string dir = test::temp_dir();
  const unsigned char px[] = {255, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0, 255};
  ASSERT_TRUE(stbi_write_png((dir + "/updown.png").c_str(), 2, 2, 3, px, 6));
  Scene s;
  TextureLibrary lib(s);
  std::vector<std::string> warnings;
  // Neither texture 0 nor at texel 0, so index and offset both matter.
  lib.checker(vec3(0), vec3(1), 1.0f);
  const unsigned char grey[] = {9, 9, 9};
  ASSERT_TRUE(stbi_write_png((dir + "/first.png").c_str(), 1, 1, 3, grey, 3));
  lib.image("first.png", dir, "x", warnings);
  const int index = lib.image("updown.png", dir, "x", warnings);
  ASSERT_EQ(index, 2);
  ASSERT_TRUE(warnings.empty());
  cl::Program program = test::build_test_kernel("textures_sample.cl", "-DHAS_TEXTURES").program;
  cl::Kernel k(program, "sample");
  const std::vector<int> indices = {index, index};
  const std::vector<float> uv = {0.25f, 0.75f, 0.75f, 0.25f};
  std::vector<cl::Buffer> keep = {upload(s.textures), upload(s.texels), upload(indices), upload(uv)};
  for (int a = 0; a < 4; ++a) k.setArg(a, keep[a]);
  k.setArg(4, cl_uint(2));
  cl::Buffer out(runtime().context(), CL_MEM_WRITE_ONLY, 2 * sizeof(cs_float4));
  k.setArg(5, out);
  runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(2));
  cs_float4 o[2];
  runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(o), o);
  EXPECT_EQ(to_vec3(o[0]), vec3(1, 0, 0));
  EXPECT_EQ(to_vec3(o[1]), vec3(0, 0, 1));
}

}  // namespace
}  // namespace caustica
