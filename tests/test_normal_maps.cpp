// glTF normal maps (issue 43): tangents from the TANGENT attribute or
// computed by MikkTSpace's rules (host/scene/mesh_tangents.cpp), the
// tangent-space texel turned into a shading normal in the kernels
// (kernels/lib/normal_map.h), and the rule that keeps a mapped normal from
// leaking or losing light (normal_with_valid_reflection, lib/optics.h).
// Checked against what is known exactly: the tangent of a plane with
// linear uv, the Lambertian shading of the perturbed normal under a
// directional light, and the furnace: a white Lambertian whose normal
// leans by theta from the geometric one reflects (1 + cos theta) / 2 of a
// uniform sky (the share of the cosine lobe about the leaning normal that
// lies above the surface; the rest is lost, never created).
#include <gtest/gtest.h>

#include <glm/gtc/packing.hpp>

#include <cmath>
#include <optional>
#include <random>

#include "host/scene/load_scene.h"
#include "host/scene/mesh_tangents.h"
#include "lib/optics.h"
#include "tests/support/gltf_doc.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;
using test::Doc;

// ---- tangents -------------------------------------------------------------

TEST(MikkTSpaceTangents, APlaneWithLinearUvHasTheUDirectionAsItsTangent) {
  // Two triangles of the square x, z in [0, 2], normal +y, u = x / 2 and
  // v = 1 - z / 2 (v up the image: increasing v runs toward -z).
  const std::vector<glm::vec3> p = {{0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}};
  const std::vector<glm::vec3> n(4, glm::vec3(0, 1, 0));
  const std::vector<glm::vec2> uv = {{0, 1}, {0, 0}, {1, 0}, {1, 1}};
  const std::vector<uint32_t> corners = {0, 1, 2, 0, 2, 3};
  const std::vector<glm::vec4> t = mikktspace_corner_tangents(p, n, uv, corners);
  ASSERT_EQ(t.size(), 6u);
  for (const glm::vec4& c : t) {
    EXPECT_NEAR(c.x, 1.0f, 1e-6f);
    EXPECT_NEAR(c.y, 0.0f, 1e-6f);
    EXPECT_NEAR(c.z, 0.0f, 1e-6f);
    // B = w cross(N, T) = w cross(+y, +x) = -w z: along increasing v.
    EXPECT_EQ(c.w, 1.0f);
  }
  // Mirrored u (a mirrored uv island): the tangent turns around and the
  // bitangent keeps pointing up the image, so w flips.
  std::vector<glm::vec2> mirrored = uv;
  for (glm::vec2& c : mirrored) c.x = 1.0f - c.x;
  for (const glm::vec4& c : mikktspace_corner_tangents(p, n, mirrored, corners)) {
    EXPECT_NEAR(c.x, -1.0f, 1e-6f);
    EXPECT_EQ(c.w, -1.0f);
  }
}

TEST(MikkTSpaceTangents, SharedVerticesAverageByAngleAndSplitByHandedness) {
  // A roof of two faces meeting at the ridge x = 0, smooth normals at the
  // ridge; u runs across the ridge: the ridge's tangent is the average
  // of the two faces', made perpendicular to its normal (+y).
  const std::vector<glm::vec3> p = {{-1, 0, 0}, {-1, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 0, 1}, {1, 0, 0}};
  std::vector<glm::vec3> n = {{-1, 1, 0}, {-1, 1, 0}, {0, 1, 0}, {0, 1, 0}, {1, 1, 0}, {1, 1, 0}};
  for (glm::vec3& v : n) v = glm::normalize(v);
  const std::vector<glm::vec2> uv = {{0, 0}, {0, 1}, {0.5f, 1}, {0.5f, 0}, {1, 1}, {1, 0}};
  const std::vector<uint32_t> corners = {0, 3, 2, 0, 2, 1, 3, 5, 4, 3, 4, 2};
  const std::vector<glm::vec4> t = mikktspace_corner_tangents(p, n, uv, corners);
  for (size_t c = 0; c < corners.size(); ++c) {
    const glm::vec3 tc(t[c]);
    EXPECT_NEAR(glm::length(tc), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(tc, n[corners[c]]), 0.0f, 1e-5f) << "corner " << c;
    if (corners[c] == 2 || corners[c] == 3) EXPECT_NEAR(tc.x, 1.0f, 1e-5f) << "the ridge's tangent is +x";
  }
  // The same ridge with the second face's u mirrored: the ridge vertices
  // are shared by faces of opposite handedness, and each keeps its own.
  std::vector<glm::vec2> seam = uv;
  seam[4].x = seam[5].x = 0.0f;
  const std::vector<glm::vec4> s = mikktspace_corner_tangents(p, n, seam, corners);
  for (size_t c = 0; c < 6; ++c) EXPECT_EQ(s[c].w, t[c].w) << "the first face keeps its frame";
  for (size_t c = 6; c < 12; ++c) {
    EXPECT_EQ(s[c].w, -t[c].w) << "the mirrored face's handedness";
    EXPECT_LT(s[c].x, -0.5f) << "its tangent points the other way";
  }
}

TEST(MikkTSpaceTangents, DegenerateUvGivesAUnitTangentPerpendicularToTheNormal) {
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<glm::vec2> uv(3, glm::vec2(0.5f));
  const std::vector<glm::vec4> t = mikktspace_corner_tangents(p, {}, uv, {0, 1, 2});
  for (const glm::vec4& c : t) {
    EXPECT_NEAR(glm::length(glm::vec3(c)), 1.0f, 1e-5f);
    EXPECT_NEAR(c.z, 0.0f, 1e-5f);  // the flat normal is +z
    EXPECT_EQ(std::fabs(c.w), 1.0f);
  }
}

// ---- the leak rule --------------------------------------------------------

TEST(NormalMapLeakRule, KeepsValidNormalsAndLiftsTheReflectionOfOthersJustAboveTheSurface) {
  const float3 ng = make_float3(0, 0, 1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int moved = 0;
  for (int i = 0; i < 20000; ++i) {
    float3 wo = make_float3(u(rng), u(rng), std::fabs(u(rng)) + 1e-3f);
    float3 n = make_float3(u(rng), u(rng), std::fabs(u(rng)) + 1e-3f);
    wo = normalize(wo);
    n = normalize(n);
    const float q = std::fmin(0.9f * dot(wo, ng), 0.01f);
    const float3 r = 2.0f * dot(wo, n) * n - wo;
    const float3 m = normal_with_valid_reflection(n, ng, wo);
    EXPECT_NEAR(length(m), 1.0f, 1e-5f);
    EXPECT_GE(dot(m, ng), 0.0f);
    if (dot(r, ng) >= q) {
      EXPECT_EQ(m.x, n.x);  // a valid normal is left exactly as it is
      EXPECT_EQ(m.z, n.z);
      continue;
    }
    ++moved;
    const float3 rm = 2.0f * dot(wo, m) * m - wo;
    EXPECT_NEAR(dot(rm, ng), q, 2e-4f) << "the new reflection rises exactly q";
    // Its azimuth is the old reflection's.
    const float az = std::atan2(rm.y, rm.x), az_old = std::atan2(r.y, r.x);
    if (std::hypot(r.x, r.y) > 1e-2f) EXPECT_NEAR(std::cos(az - az_old), 1.0f, 1e-3f);
  }
  EXPECT_GT(moved, 2000) << "the random normals include many that lean too far";
}

// ---- import and render ----------------------------------------------------

// A w x w binary PPM of one colour (8-bit codes).
std::string ppm_constant(glm::ivec3 c, int w = 2) {
  std::string s = "P6 " + std::to_string(w) + " " + std::to_string(w) + " 255\n";
  for (int i = 0; i < w * w; ++i) s += {char(c.x), char(c.y), char(c.z)};
  return s;
}

// The 8-bit codes of tangent-space normal n (rgb = (n + 1) / 2), and the
// normal those codes decode to as the kernels read them (half floats).
glm::ivec3 codes_of(glm::vec3 n) { return glm::ivec3(glm::round((n + 1.0f) * 0.5f * 255.0f)); }
glm::vec3 decoded(glm::ivec3 c) {
  glm::vec3 t;
  for (int i = 0; i < 3; ++i) t[i] = glm::unpackHalf1x16(glm::packHalf1x16(float(c[i]) / 255.0f));
  return 2.0f * t - 1.0f;
}

struct QuadOptions {
  std::optional<std::string> normal_image;  // a PPM; none: no normal map
  std::optional<glm::vec4> tangent;         // the TANGENT attribute of every vertex; none: MikkTSpace's
  double scale = 1.0;                       // normalTexture.scale
  double ior = 1.0;  // 1: no specular layer (F0 = 0), an exact Lambertian
};

// The square x, z in [-1, 1] of y = 0 (normal +y), glTF uv u = (x + 1) / 2,
// v = (z + 1) / 2: the tangent is +x, the bitangent (up the image) -z;
// white, with the normal map and tangents asked for.
std::string quad_file(const QuadOptions& o) {
  Doc d;
  const std::vector<float> pos = {-1, 0, -1, -1, 0, 1, 1, 0, 1, 1, 0, -1};
  const std::vector<float> uv = {0, 0, 0, 1, 1, 1, 1, 0};
  const std::vector<float> normals = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  json attributes = {{"POSITION", d.floats(pos, "VEC3", 3)},
                     {"NORMAL", d.floats(normals, "VEC3", 3)},
                     {"TEXCOORD_0", d.floats(uv, "VEC2", 2)}};
  if (o.tangent) {
    std::vector<float> t;
    for (int i = 0; i < 4; ++i) t.insert(t.end(), {o.tangent->x, o.tangent->y, o.tangent->z, o.tangent->w});
    attributes["TANGENT"] = d.floats(t, "VEC4", 4);
  }
  json material = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0.0},
                                             {"roughnessFactor", 0.5}}},
                   {"extensions", {{"KHR_materials_ior", {{"ior", o.ior}}}}}};
  d.j["extensionsUsed"] = {"KHR_materials_ior"};
  if (o.normal_image) {
    d.j["images"] = {{{"bufferView", d.view(*o.normal_image)}, {"mimeType", "image/png"}}};
    d.j["textures"] = {{{"source", 0}}};
    material["normalTexture"] = {{"index", 0}, {"scale", o.scale}};
  }
  d.j["materials"] = {material};
  d.j["meshes"] = {{{"primitives", {{{"attributes", attributes},
                                     {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
                                     {"material", 0}}}}}};
  d.node({{"mesh", 0}});
  return d.text();
}

// The quad seen from straight above (its whole view is the quad), under a
// directional light from `to_light` with one scattering event (direct
// light only), or under a white sky with none and many bounces.
std::string quad_scene(const std::string& name, const QuadOptions& o, std::optional<glm::vec3> to_light) {
  test::write_scene(name + ".gltf", quad_file(o));
  std::string lights = "[]", background = "[1, 1, 1]", bounces = "8";
  if (to_light) {
    const glm::vec3 d = -glm::normalize(*to_light);
    lights = "[{\"type\": \"directional\", \"direction\": [" + std::to_string(d.x) + ", " + std::to_string(d.y) +
             ", " + std::to_string(d.z) + "], \"intensity\": [2, 2, 2]}]";
    background = "[0, 0, 0]";
    bounces = "1";
  }
  return test::write_scene(name + ".json", R"({"rendermode": "pathtracer", "nbounces": )" + bounces + R"(,
    "camera": {"width": 16, "height": 16, "position": [0, 3, 0], "lookAt": [0, 0, 0], "upVector": [0, 0, -1],
               "fov": 30},
    "scene": {"backgroundcolor": )" + background + R"(, "lightsources": )" + lights + R"(,
      "shapes": [{"type": "mesh", "file": ")" + name + R"(.gltf"}]}})");
}

TEST(NormalMaps, ImportReadsTheMapItsScaleAndTangentsWithoutAWarning) {
  QuadOptions o;
  o.normal_image = ppm_constant(codes_of(glm::vec3(0, 0, 1)));
  o.scale = 0.75;
  std::vector<std::string> warnings;
  LoadOptions lo;
  lo.warnings = &warnings;
  const Scene s = load_scene(quad_scene("nm_import", o, glm::vec3(0, 1, 0)), lo);
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_GE(s.materials[0].normal_texture, 0);
  EXPECT_FLOAT_EQ(s.materials[0].normal_scale, 0.75f);
  ASSERT_EQ(s.triangle_tangents.size(), s.triangles.size());
  for (const TriangleTangents& t : s.triangle_tangents)
    for (const cs_float4& c : {t.t0, t.t1, t.t2}) {
      EXPECT_NEAR(c.x, 1.0f, 1e-6f);
      EXPECT_EQ(c.w, 1.0f);
    }
  // Without a normal map nothing is stored, and the program leaves it out.
  const Scene plain = load_scene(quad_scene("nm_plain", QuadOptions{}, glm::vec3(0, 1, 0)));
  EXPECT_TRUE(plain.triangle_tangents.empty());
}

// The quad's mean radiance with and without the map: a Lambertian under a
// directional light gives (rho / pi) E max(0, n . l), so their ratio is
// max(0, n . l) / (ng . l) for the mapped normal n, whatever E and rho.
double shading_ratio(const std::string& name, QuadOptions o, glm::vec3 to_light) {
  const int spp = 4;  // a uniform plane under a delta light: no noise to average
  const test::PathRender mapped = test::render_path(quad_scene(name, o, to_light), spp);
  o.normal_image.reset();
  const test::PathRender flat = test::render_path(quad_scene(name + "_flat", o, to_light), spp);
  const double a = test::mean_all(mapped).mean, b = test::mean_all(flat).mean;
  EXPECT_GT(b, 0.0);
  return a / b;
}

// The mapped normal in world space: tangent-space n in the frame (T, B, N).
double expected_ratio(glm::vec3 tangent_space, glm::vec3 t, glm::vec3 b, float scale, glm::vec3 to_light) {
  const glm::vec3 n = glm::normalize(scale * tangent_space.x * t + scale * tangent_space.y * b +
                                     tangent_space.z * glm::vec3(0, 1, 0));
  const glm::vec3 l = glm::normalize(to_light);
  return std::max(0.0f, glm::dot(n, l)) / l.y;
}

TEST(NormalMaps, APlaneShadesAsItsPerturbedNormalUnderADirectionalLight) {
  const float theta = 0.5f;
  const glm::ivec3 red_tilt = codes_of(glm::vec3(std::sin(theta), 0, std::cos(theta)));
  const glm::ivec3 green_tilt = codes_of(glm::vec3(0, std::sin(theta), std::cos(theta)));
  const glm::vec3 x(1, 0, 0), minus_z(0, 0, -1), z(0, 0, 1);
  struct Case {
    const char* name;
    glm::ivec3 texel;
    std::optional<glm::vec4> tangent;
    float scale;
    glm::vec3 t, b, to_light;
  };
  // MikkTSpace's frame is (+x, -z) here; a TANGENT of +z with w = 1 makes
  // it (+z, cross(+y, +z) = +x).
  const Case cases[] = {
      {"nm_red_toward", red_tilt, {}, 1.0f, x, minus_z, {0.6f, 1.0f, 0.0f}},
      {"nm_red_away", red_tilt, {}, 1.0f, x, minus_z, {-0.6f, 1.0f, 0.0f}},
      {"nm_green_toward", green_tilt, {}, 1.0f, x, minus_z, {0.0f, 1.0f, -0.6f}},
      {"nm_green_away", green_tilt, {}, 1.0f, x, minus_z, {0.0f, 1.0f, 0.6f}},
      {"nm_half_scale", red_tilt, {}, 0.5f, x, minus_z, {0.6f, 1.0f, 0.0f}},
      {"nm_tangent_attribute", red_tilt, glm::vec4(0, 0, 1, 1), 1.0f, z, x, {0.0f, 1.0f, 0.6f}},
      {"nm_tangent_attribute_green", green_tilt, glm::vec4(0, 0, 1, 1), 1.0f, z, x, {0.6f, 1.0f, 0.0f}},
  };
  for (const Case& c : cases) {
    QuadOptions o;
    o.normal_image = ppm_constant(c.texel);
    o.tangent = c.tangent;
    o.scale = c.scale;
    const double got = shading_ratio(c.name, o, c.to_light);
    const double want = expected_ratio(decoded(c.texel), c.t, c.b, c.scale, c.to_light);
    std::printf("%-28s ratio %.5f, expected %.5f\n", c.name, got, want);
    EXPECT_NEAR(got, want, 2e-3 * want) << c.name;
  }
}

// The furnace: a white Lambertian quad under a uniform white sky, nothing
// else. A normal leaning by theta gives (1 + cos theta) / 2; a bumpy map
// never more than 1.
TEST(NormalMaps, AFurnaceLosesExactlyTheLobeBelowTheSurfaceAndNeverGains) {
  const int spp = int(test::sized(128, 16));
  const float theta = 0.5f;
  QuadOptions o;
  const glm::ivec3 texel = codes_of(glm::vec3(std::sin(theta) * 0.6f, std::sin(theta) * 0.8f, std::cos(theta)));
  o.normal_image = ppm_constant(texel);
  const glm::vec3 n = glm::normalize(decoded(texel));
  const test::Mean lean = test::mean_all(test::render_path(quad_scene("nm_furnace_lean", o, {}), spp));
  const double want = 0.5 * (1.0 + double(n.z));
  std::printf("leaning normal: %.5f +- %.5f, expected %.5f\n", lean.mean, lean.se, want);
  EXPECT_NEAR(lean.mean, want, 4.0 * lean.se + 1e-4);
  EXPECT_LT(lean.se, 0.05 * (1.0 - want)) << "the test must tell the loss apart (by 20 standard errors)";

  // Bumps: 16 x 16 texels leaning up to 40 degrees every way, on the
  // Lambertian and on glTF's default plastic (a GGX layer, F0 = 0.04).
  std::string bumps = "P6 16 16 255\n";
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 256; ++i) {
    const float t = 0.7f * std::sqrt(u(rng)), phi = 6.2831853f * u(rng);
    const glm::ivec3 c = codes_of(glm::vec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)));
    bumps += {char(c.x), char(c.y), char(c.z)};
  }
  o.normal_image = bumps;
  for (double ior : {1.0, 1.5}) {
    o.ior = ior;
    const test::Mean m =
        test::mean_all(test::render_path(quad_scene(ior == 1.0 ? "nm_bumps" : "nm_bumps_plastic", o, {}), spp));
    std::printf("bumps, ior %.1f: %.5f +- %.5f\n", ior, m.mean, m.se);
    EXPECT_LE(m.mean, 1.0 + 4.0 * m.se) << "energy created";
    if (ior == 1.0)
      EXPECT_GE(m.mean, 0.5 * (1.0 + std::cos(0.7)) - 4.0 * m.se) << "more lost than the steepest texel loses";
  }
}

}  // namespace
}  // namespace caustica
