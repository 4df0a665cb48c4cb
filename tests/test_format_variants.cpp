// Student variants of the coursework format (scenes/FORMAT.md): each spelling
// must land in the same canonical Scene field as its canonical form.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/error.h"
#include "host/scene/load_scene.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;

using test::Contains;

// A scene with no shapes or lights yet: tests add the variant under test.
json base_scene() {
  return json::parse(R"({
    "nbounces": 3, "rendermode": "phong",
    "camera": {"type": "pinhole", "width": 64, "height": 32, "position": [0, 0, 0],
               "lookAt": [0, 0, 4], "upVector": [0, 1, 0], "fov": 45, "exposure": 0.1},
    "scene": {"backgroundcolor": [0.1, 0.2, 0.3], "lightsources": [], "shapes": []}})");
}

json with_shape(json j, const json& shape) {
  j["scene"]["shapes"].push_back(shape);
  return j;
}
json with_light(json j, const json& light) {
  j["scene"]["lightsources"].push_back(light);
  return j;
}

struct Loaded {
  Scene scene;
  std::vector<std::string> warnings;
};

Loaded parse(const json& j, const std::string& dir = ".", bool strict = false) {
  Loaded out;
  LoadOptions options;
  options.warnings = &out.warnings;
  options.strict = strict;
  out.scene = parse_scene(j, "x.json", dir, options);
  return out;
}

std::string error_of(const json& j, const std::string& dir = ".", bool strict = false) {
  try {
    parse(j, dir, strict);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected caustica::Error";
  return {};
}

std::string write_file(const std::string& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir + "/" + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// A 2x1 binary PPM: one red, one blue texel.
std::string tiny_ppm() { return std::string("P6\n2 1\n255\n") + std::string("\xff\x00\x00\x00\x00\xff", 6); }

void expect_vec3(const cs_float4& got, const glm::vec3& want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}
void expect_vec3(const glm::vec3& got, const glm::vec3& want, float tol = 1e-5f) {
  expect_vec3(to_float4(got), want, tol);
}

glm::vec3 normal_of(const Triangle& t) {
  return glm::normalize(glm::cross(to_vec3(t.v1) - to_vec3(t.v0), to_vec3(t.v2) - to_vec3(t.v0)));
}

const json kSphere = {{"type", "sphere"}, {"center", {0, 0, 3}}, {"radius", 0.5}};

// ---------------------------------------------------------------- render mode and camera

// The loader records the file's choice; whether the mode is built is the
// renderer's business (tests/test_render_core.cpp).
TEST(FormatVariants, PathTracingModesLoadAsPath) {
  for (const char* name : {"pathtracer", "pathtracing", "path", "PathTracer"}) {
    json j = with_shape(base_scene(), kSphere);
    j["rendermode"] = name;
    EXPECT_EQ(parse_scene(j, "x.json", ".").mode, RenderMode::Path) << name;
  }
  json j = base_scene();
  j["rendermode"] = "Phong";
  EXPECT_EQ(parse(with_shape(j, kSphere)).scene.mode, RenderMode::Phong);
}

TEST(FormatVariants, ApertureAndFocusSpellings) {
  // Every aperture spelling is the lens diameter.
  for (const char* type : {"finiteAperture", "finite-aperture", "thinlens", "aperture", "pinhole"})
    for (const char* aperture : {"aperture", "apertureSize", "diameter"})
      for (const char* focus : {"focalDistance", "focusDistance", "focusdistance", "focalLength", "focus_distance"}) {
        json j = with_shape(base_scene(), kSphere);
        j["camera"]["type"] = type;
        j["camera"][aperture] = 0.2;
        j["camera"][focus] = 2.5;
        const Loaded l = parse(j);
        EXPECT_FLOAT_EQ(l.scene.camera.aperture_radius, 0.1f) << type << " " << aperture;
        EXPECT_FLOAT_EQ(l.scene.camera.focus_distance, 2.5f) << focus;
        EXPECT_TRUE(l.warnings.empty()) << l.warnings.front();
      }
  // No focus key: the look-at point is in focus. No aperture: a pinhole.
  const Loaded plain = parse(with_shape(base_scene(), kSphere));
  EXPECT_FLOAT_EQ(plain.scene.camera.aperture_radius, 0.0f);
  EXPECT_FLOAT_EQ(plain.scene.camera.focus_distance, 4.0f);
}

TEST(FormatVariants, TopLevelDepthOfField) {
  json j = with_shape(base_scene(), kSphere);
  j["use_dof"] = true;
  j["aperture"] = 0.6;
  j["focus_distance"] = 6.0;
  Loaded l = parse(j);
  EXPECT_FLOAT_EQ(l.scene.camera.aperture_radius, 0.3f);
  EXPECT_FLOAT_EQ(l.scene.camera.focus_distance, 6.0f);
  EXPECT_TRUE(l.warnings.empty());
  j["use_dof"] = false;
  EXPECT_FLOAT_EQ(parse(j).scene.camera.aperture_radius, 0.0f);
  // The camera's own keys win over the top-level ones.
  j["use_dof"] = true;
  j["camera"]["apertureSize"] = 0.1;
  EXPECT_FLOAT_EQ(parse(j).scene.camera.aperture_radius, 0.05f);
  j["camera"]["aperture"] = -1;
  j["camera"].erase("apertureSize");
  EXPECT_TRUE(Contains(error_of(j), {"x.json: /camera/aperture: expected a non-negative finite number, got -1"}));
}

TEST(FormatVariants, AnimatedCameraUsesTheFirstKeyframe) {
  json j = with_shape(base_scene(), kSphere);
  j["camera"].erase("position");
  j["camera"]["position0"] = {-2, 0, 0};
  j["camera"]["position1"] = {0, 0, 0};
  j["camera"]["movement0"] = {0, 125};
  j["FramesNum"] = 250;
  const Loaded l = parse(j);
  EXPECT_EQ(l.scene.camera.position, glm::vec3(-2, 0, 0));
  ASSERT_EQ(l.warnings.size(), 1u);
  EXPECT_TRUE(Contains(l.warnings[0], {"x.json: /: warning: animation", "not supported"}));
}

// ---------------------------------------------------------------- lights

TEST(FormatVariants, AreaLightEdgeSpellingsAgree) {
  const json common = {{"type", "arealight"}, {"position", {0, 2, 0}}, {"intensity", {1, 1, 1}}};
  auto light = [&](const json& extra) {
    json l = common;
    l.update(extra);
    const Loaded loaded = parse(with_light(with_shape(base_scene(), kSphere), l));
    EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
    EXPECT_EQ(lights_of_kind(loaded.scene, LIGHT_RECT).size(), 1u);
    return loaded.scene;
  };
  const Scene uv = light({{"u", {0.5, 0, 0}}, {"v", {0, 0, 0.25}}, {"samples", 16}});
  const Scene axis = light({{"u_axis", {0.5, 0, 0}}, {"v_axis", {0, 0, 0.25}}});
  const Scene wh = light({{"u", {1, 0, 0}}, {"v", {0, 0, 2}}, {"width", 0.5}, {"height", 0.25}});
  const Scene size = light({{"size", {0.5, 0.25}}});  // default axes: x and z
  for (const Scene* s : {&uv, &axis, &wh, &size}) {
    const Light& a = s->lights[0];  // centre, edge vectors u and v (kernels/lib/lights/rect_light.h)
    expect_vec3(to_vec3(a.p0), glm::vec3(0, 2, 0));
    expect_vec3(to_vec3(a.p1), glm::vec3(0.5, 0, 0));
    expect_vec3(to_vec3(a.p2), glm::vec3(0, 0, 0.25));
    expect_vec3(to_vec3(a.emitted), glm::vec3(1));
    EXPECT_FLOAT_EQ(a.emitted.w, 0.125f);  // the area
    // Phong renders it as a point light at its centre.
    EXPECT_TRUE(lights_of_kind(*s, LIGHT_POINT).empty());  // kept as an area light, not turned into a point light
    const std::vector<Light> stand_ins = whitted_lights(*s);
    ASSERT_EQ(stand_ins.size(), 1u);
    EXPECT_EQ(stand_ins[0].kind, uint32_t(LIGHT_POINT));
    expect_vec3(to_vec3(stand_ins[0].p0), glm::vec3(0, 2, 0));
    expect_vec3(to_vec3(stand_ins[0].emitted), glm::vec3(1));
  }
  // Default axes face down: cross(u, v) = -y.
  expect_vec3(glm::normalize(glm::cross(to_vec3(size.lights[0].p1), to_vec3(size.lights[0].p2))), glm::vec3(0, -1, 0));

  // Nothing but a position: a small square, with a warning.
  const Loaded bare = parse(with_light(with_shape(base_scene(), kSphere), common));
  ASSERT_EQ(lights_of_kind(bare.scene, LIGHT_RECT).size(), 1u);
  EXPECT_FLOAT_EQ(glm::length(to_vec3(bare.scene.lights[0].p1)), 0.1f);
  ASSERT_EQ(bare.warnings.size(), 1u);
  EXPECT_TRUE(Contains(bare.warnings[0], {"/scene/lightsources/0: warning: area light without a size"}));

  json half = common;
  half["u"] = {1, 0, 0};
  EXPECT_TRUE(Contains(error_of(with_light(base_scene(), half)), {"/scene/lightsources/0/u: expected both"}));
  json parallel = common;
  parallel["u"] = {1, 0, 0};
  parallel["v"] = {2, 0, 0};
  EXPECT_TRUE(Contains(error_of(with_light(base_scene(), parallel)), {"/scene/lightsources/0: expected edge vectors"}));
}

TEST(FormatVariants, SphereAndAmbientLights) {
  json j = with_shape(base_scene(), kSphere);
  j = with_light(j, {{"type", "pointlight"}, {"position", {0, 1, 0}}, {"intensity", {0.5, 0.5, 0.5}}});
  j = with_light(j, {{"type", "spherelight"}, {"position", {1, 1, 1}}, {"radius", 0.25}, {"intensity", {2, 2, 2}}});
  j = with_light(j, {{"type", "ambient"}, {"intensity", {0.1, 0.1, 0.1}}});
  j["scene"]["ambientlight"] = {0.2, 0.3, 0.4};
  const Loaded l = parse(j);
  EXPECT_TRUE(l.warnings.empty());
  ASSERT_EQ(lights_of_kind(l.scene, LIGHT_SPHERE).size(), 1u);
  EXPECT_FLOAT_EQ(lights_of_kind(l.scene, LIGHT_SPHERE)[0].p0.w, 0.25f);  // the radius
  ASSERT_EQ(lights_of_kind(l.scene, LIGHT_POINT).size(), 1u);
  const std::vector<Light> stand_ins = whitted_lights(l.scene);
  ASSERT_EQ(stand_ins.size(), 2u);  // phong: the point light and the sphere light's stand-in
  expect_vec3(to_vec3(stand_ins[1].p0), glm::vec3(1, 1, 1));
  ASSERT_TRUE(l.scene.ambient_light.has_value());
  expect_vec3(*l.scene.ambient_light, glm::vec3(0.3f, 0.4f, 0.5f));  // both forms add
  EXPECT_FALSE(parse(with_shape(base_scene(), kSphere)).scene.ambient_light.has_value());
}

// ---------------------------------------------------------------- shapes

TEST(FormatVariants, UvSphereAndUvCylinderAreSphereAndCylinder) {
  json j = with_shape(base_scene(), {{"type", "uvsphere"}, {"center", {0, 0, 3}}, {"radius", 0.5}});
  json cyl = {{"type", "uvcylinder"}, {"center", {1, 0, 3}}, {"axis", {0, 2, 0}}, {"radius", 0.2}, {"height", 0.3}};
  j = with_shape(j, cyl);
  cyl["type"] = "cylinder";
  cyl["topmaterial"] = {{"kd", 0.5}};
  cyl["bottommaterial"] = {{"kd", 0.5}};
  j = with_shape(j, cyl);
  const Loaded l = parse(j);
  EXPECT_EQ(l.scene.spheres.size(), 1u);
  ASSERT_EQ(l.scene.cylinders.size(), 2u);
  EXPECT_EQ(to_vec3(l.scene.cylinders[0].axis_half), glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(l.scene.cylinders[0].axis_half.w, 0.3f);
  ASSERT_EQ(l.warnings.size(), 1u);  // the two cap materials: one grouped warning
  EXPECT_TRUE(Contains(l.warnings[0], {"/scene/shapes/2/topmaterial: warning", "caps use the side", "1 more"}));
}

TEST(FormatVariants, EnvironmentMapShapesAreSkipped) {
  json j = with_shape(base_scene(), kSphere);
  j = with_shape(j, {{"type", "cubemap"}, {"center", {0, 0, 1}}, {"radius", 0.1}});
  const Loaded l = parse(j);
  EXPECT_EQ(l.scene.primitive_count(), 1u);
  ASSERT_EQ(l.warnings.size(), 1u);
  EXPECT_TRUE(Contains(l.warnings[0], {"/scene/shapes/1: warning: shape type \"cubemap\" skipped",
                                       "environment maps are not supported"}));
}

TEST(FormatVariants, TriangleUvsGiveShadingToEveryTriangle) {
  json j = base_scene();
  j = with_shape(j, {{"type", "triangle"}, {"v0", {0, 0, 2}}, {"v1", {1, 0, 2}}, {"v2", {0, 1, 2}}});
  const Loaded none = parse(j);
  EXPECT_TRUE(none.scene.triangle_shading.empty());  // no triangle has data: none stored
  j = with_shape(j, {{"type", "triangle"},
                     {"v0", {0, 0, 3}},
                     {"v1", {0, 1, 3}},
                     {"v2", {1, 0, 3}},
                     {"uv0", {0, 0}},
                     {"uv1", {5, 0}},
                     {"uv2", {5, 4}}});
  const Loaded l = parse(j);
  ASSERT_EQ(l.scene.triangles.size(), 2u);
  ASSERT_EQ(l.scene.triangle_shading.size(), 2u);
  const TriangleShading& a = l.scene.triangle_shading[0];  // no data: geometric normal, default UVs
  expect_vec3(a.n0, glm::vec3(0, 0, 1));
  expect_vec3(a.n2, glm::vec3(0, 0, 1));
  EXPECT_EQ(glm::vec2(a.u0, a.v0), glm::vec2(0, 0));
  EXPECT_EQ(glm::vec2(a.u1, a.v1), glm::vec2(1, 0));
  EXPECT_EQ(glm::vec2(a.u2, a.v2), glm::vec2(0, 1));
  const TriangleShading& b = l.scene.triangle_shading[1];
  expect_vec3(b.n1, glm::vec3(0, 0, -1));
  EXPECT_EQ(glm::vec2(b.u1, b.v1), glm::vec2(5, 0));
  EXPECT_EQ(glm::vec2(b.u2, b.v2), glm::vec2(5, 4));

  json partial = with_shape(base_scene(), {{"type", "triangle"}, {"v0", {0, 0, 2}}, {"v1", {1, 0, 2}},
                                           {"v2", {0, 1, 2}}, {"uv0", {0, 0}}});
  EXPECT_TRUE(Contains(error_of(partial), {"/scene/shapes/0/uv1: required key \"uv1\" is missing"}));
}

TEST(FormatVariants, RectangleFromFourVertices) {
  const json j = with_shape(base_scene(), {{"type", "rectangle"},
                                           {"v0", {0, 0, 5}},
                                           {"v1", {5, 0, 5}},
                                           {"v2", {5, 0, 0}},
                                           {"v3", {0, 0, 0}},
                                           {"_comment", "floor"}});
  const Loaded l = parse(j);
  EXPECT_TRUE(l.warnings.empty());
  ASSERT_EQ(l.scene.triangles.size(), 2u);
  const Triangle& t0 = l.scene.triangles[0];
  const Triangle& t1 = l.scene.triangles[1];
  expect_vec3(t0.v0, glm::vec3(0, 0, 5));
  expect_vec3(t0.v1, glm::vec3(5, 0, 5));
  expect_vec3(t0.v2, glm::vec3(5, 0, 0));
  expect_vec3(t1.v0, glm::vec3(0, 0, 5));
  expect_vec3(t1.v1, glm::vec3(5, 0, 0));
  expect_vec3(t1.v2, glm::vec3(0, 0, 0));
  ASSERT_EQ(l.scene.triangle_shading.size(), 2u);
  const TriangleShading& s1 = l.scene.triangle_shading[1];
  EXPECT_EQ(glm::vec2(s1.u1, s1.v1), glm::vec2(1, 1));
  EXPECT_EQ(glm::vec2(s1.u2, s1.v2), glm::vec2(0, 1));
}

TEST(FormatVariants, RectangleFromTwoCorners) {
  const Loaded l =
      parse(with_shape(base_scene(), {{"type", "rectangle"}, {"corner1", {-1, 0, 2}}, {"corner2", {1, 0.0, 0}}}));
  ASSERT_EQ(l.scene.triangles.size(), 2u);
  // Flat in y: the quad (z, x) = (0,-1), (2,-1), (2,1), (0,1) at y = 0, facing +y.
  const Triangle& t0 = l.scene.triangles[0];
  expect_vec3(t0.v0, glm::vec3(-1, 0, 0));
  expect_vec3(t0.v1, glm::vec3(-1, 0, 2));
  expect_vec3(t0.v2, glm::vec3(1, 0, 2));
  expect_vec3(l.scene.triangles[1].v2, glm::vec3(1, 0, 0));
  expect_vec3(normal_of(t0), glm::vec3(0, 1, 0));
  expect_vec3(normal_of(l.scene.triangles[1]), glm::vec3(0, 1, 0));

  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "rectangle"}, {"corner1", {0, 0, 0}},
                                                          {"corner2", {1, 1, 1}}})),
                       {"/scene/shapes/0/corner2: expected the opposite corner of an axis-aligned rectangle"}));
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "rectangle"}, {"v0", {0, 0, 0}}})),
                       {"/scene/shapes/0/v1: required key \"v1\" is missing"}));
}

TEST(FormatVariants, BoxIsTwelveOutwardTriangles) {
  const json box = {{"type", "box"}, {"min", {2, 0, 3}}, {"max", {1, 3, 1}}};  // corners in any order
  const Loaded l = parse(with_shape(base_scene(), box));
  ASSERT_EQ(l.scene.triangles.size(), 12u);
  ASSERT_EQ(l.scene.triangle_shading.size(), 12u);
  const glm::vec3 centre(1.5f, 1.5f, 2.0f);
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const Triangle& t : l.scene.triangles) {
    for (const cs_float4* v : {&t.v0, &t.v1, &t.v2}) {
      lo = glm::min(lo, to_vec3(*v));
      hi = glm::max(hi, to_vec3(*v));
    }
    const glm::vec3 mid = (to_vec3(t.v0) + to_vec3(t.v1) + to_vec3(t.v2)) / 3.0f;
    EXPECT_GT(glm::dot(normal_of(t), mid - centre), 0.0f);  // faces outward
  }
  expect_vec3(lo, glm::vec3(1, 0, 1));
  expect_vec3(hi, glm::vec3(2, 3, 3));

  // rotation: degrees about x, then y, then z, about the world origin.
  json rotated = box;
  rotated["rotation"] = {0, 90, 0};
  const Loaded r = parse(with_shape(base_scene(), rotated));
  lo = glm::vec3(1e9f), hi = glm::vec3(-1e9f);
  for (const Triangle& t : r.scene.triangles)
    for (const cs_float4* v : {&t.v0, &t.v1, &t.v2}) {
      lo = glm::min(lo, to_vec3(*v));
      hi = glm::max(hi, to_vec3(*v));
    }
  // (x, y, z) -> (z, y, -x)
  expect_vec3(lo, glm::vec3(1, 0, -2), 1e-5f);
  expect_vec3(hi, glm::vec3(3, 3, -1), 1e-5f);

  json flat = box;
  flat["max"] = {1, 3, 3};
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), flat)), {"/scene/shapes/0/max: expected a corner that differs"}));
}

class MeshFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir();
    write_file(dir_, "models/tiny.obj",
               "mtllib tiny.mtl\n"
               "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
               "vt 0 0\nvt 1 0\nvt 0 1\n"
               "vn 0 0 1\n"
               "usemtl red\n"
               "f 1/1/1 2/2/1 3/3/1\n");
    write_file(dir_, "models/tiny.mtl", "newmtl red\nKd 0.9 0.1 0.1\nKs 0.5 0.5 0.5\nNs 64\nKe 0.2 0 0\nmap_Kd tex.ppm\n");
    write_file(dir_, "models/tex.ppm", tiny_ppm());
  }
  std::string dir_;
};

TEST_F(MeshFixture, TransformAppliesToPositionsAndNormals) {
  json mesh = {{"type", "mesh"},
               {"file", "models/tiny.obj"},
               {"transform", {{"translate", {1, 2, 3}}, {"scale", 2}, {"rotate", {0, 90, 0}}}}};
  const Loaded l = parse(with_shape(base_scene(), mesh), dir_);
  ASSERT_EQ(l.scene.triangles.size(), 1u);
  const Triangle& t = l.scene.triangles[0];
  // scale 2, then (x, y, z) -> (z, y, -x), then + (1, 2, 3).
  expect_vec3(t.v0, glm::vec3(1, 2, 3));
  expect_vec3(t.v1, glm::vec3(1, 2, 1));
  expect_vec3(t.v2, glm::vec3(1, 4, 3));
  ASSERT_EQ(l.scene.triangle_shading.size(), 1u);
  expect_vec3(l.scene.triangle_shading[0].n0, glm::vec3(1, 0, 0));
  expect_vec3(normal_of(t), glm::vec3(1, 0, 0));
  ASSERT_EQ(l.scene.meshes.size(), 1u);
  EXPECT_EQ(l.scene.meshes[0].triangles, 1u);
  EXPECT_NE(l.scene.meshes[0].file.find("tiny.obj"), std::string::npos);

  // The MTL material: Kd, Ks (ks = 1), Ns, Ke, map_Kd.
  const Material& m = l.scene.materials[t.material];
  expect_vec3(m.diffuse, glm::vec3(0.9f, 0.1f, 0.1f));
  expect_vec3(m.specular, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(m.specular.w, 1.0f);
  EXPECT_FLOAT_EQ(m.specular_exponent, 64.0f);
  expect_vec3(m.emission, glm::vec3(0.2f, 0, 0));
  ASSERT_GE(m.texture, 0);
  EXPECT_EQ(l.scene.textures[static_cast<size_t>(m.texture)].kind, TEXTURE_IMAGE);
  EXPECT_TRUE(l.warnings.empty()) << l.warnings.front();

  // The PLY variant's offset / scale / euler mean the same.
  json ply = {{"type", "ply"},  {"path", "models/tiny.obj"}, {"offset", {1, 2, 3}},
              {"scale", {2, 2, 2}}, {"euler", {0, 90, 0}}, {"alias", "tiny"}};
  const Loaded p = parse(with_shape(base_scene(), ply), dir_);
  ASSERT_EQ(p.scene.triangles.size(), 1u);
  expect_vec3(p.scene.triangles[0].v1, glm::vec3(1, 2, 1));
  expect_vec3(p.scene.triangles[0].v2, glm::vec3(1, 4, 3));
}

TEST_F(MeshFixture, MirroringScaleKeepsTheWindingOutward) {
  json mesh = {{"type", "mesh"}, {"filename", "models/tiny.obj"}, {"transform", {{"scale", {-1, 1, 1}}}}};
  const Loaded l = parse(with_shape(base_scene(), mesh), dir_);
  ASSERT_EQ(l.scene.triangles.size(), 1u);
  expect_vec3(normal_of(l.scene.triangles[0]), glm::vec3(0, 0, 1));
  expect_vec3(l.scene.triangle_shading[0].n0, glm::vec3(0, 0, 1));
}

TEST_F(MeshFixture, ShapeMaterialOverridesTheMtl) {
  json mesh = {{"type", "mesh"}, {"file", "models/tiny.obj"}, {"material", {{"diffusecolor", {0, 1, 0}}}}};
  const Loaded l = parse(with_shape(base_scene(), mesh), dir_);
  ASSERT_EQ(l.scene.materials.size(), 1u);
  expect_vec3(l.scene.materials[0].diffuse, glm::vec3(0, 1, 0));
  EXPECT_EQ(l.scene.materials[0].texture, -1);
}

TEST_F(MeshFixture, FoundByNameWhenThePathIsFromAnotherMachine) {
  const json mesh = {{"type", "mesh"}, {"file", "C:\\Users\\someone\\project\\tiny.obj"}};
  const Loaded l = parse(with_shape(base_scene(), mesh), dir_);
  EXPECT_EQ(l.scene.triangles.size(), 1u);
}

TEST_F(MeshFixture, MissingMeshIsAnErrorNamingIt) {
  const json mesh = {{"type", "mesh"}, {"filename", "models/missing.obj"}};
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), mesh), dir_),
                       {"x.json: /scene/shapes/0/filename: expected an existing mesh file, got \"models/missing.obj\""}));
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "mesh"}}), dir_),
                       {"/scene/shapes/0/file: required key \"file\" is missing"}));
  write_file(dir_, "models/broken.obj", "v 0 0 0\nf 1 2 3\n");
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "mesh"}, {"file", "models/broken.obj"}}), dir_),
                       {"x.json: /scene/shapes/0/file: cannot load mesh: ", "broken.obj"}));
}

// ---------------------------------------------------------------- materials and textures

TEST(FormatVariants, MaterialSpellings) {
  auto material = [](const json& m) {
    const Loaded l = parse(with_shape(base_scene(), {{"type", "sphere"}, {"center", {0, 0, 3}}, {"radius", 1},
                                                     {"material", m}}));
    EXPECT_TRUE(l.warnings.empty()) << l.warnings.front();
    return l.scene.materials.at(l.scene.spheres.at(0).material);
  };
  expect_vec3(material({{"basecolor", {0.1, 0.2, 0.3}}}).diffuse, glm::vec3(0.1f, 0.2f, 0.3f));
  // diffusecolor wins over the path tracer's basecolor.
  expect_vec3(material({{"diffusecolor", {1, 0, 0}}, {"basecolor", {0, 1, 0}}}).diffuse, glm::vec3(1, 0, 0));
  EXPECT_FLOAT_EQ(material({{"ka", 0.5}}).ka, 0.5f);
  EXPECT_FLOAT_EQ(material({{"roughness", 0.3}, {"transmittance", 0.5}, {"fresnelreflectance", 1.0}}).ka,
                  kDefaultAmbient);

  const Material diffuse = material({{"type", "diffuse"}, {"albedo", {0.73, 0.73, 0.73}}});
  expect_vec3(diffuse.diffuse, glm::vec3(0.73f));
  EXPECT_FLOAT_EQ(diffuse.diffuse.w, 1.0f);
  EXPECT_FLOAT_EQ(diffuse.specular.w, 0.0f);
  EXPECT_EQ(diffuse.flags, 0u);
  EXPECT_EQ(material({{"type", "metal"}, {"albedo", {0.7, 0.7, 0.7}}}).flags, MATERIAL_REFLECTIVE);
  const Material glass = material({{"type", "dielectric"}, {"ior", 1.5}});
  EXPECT_EQ(glass.flags, MATERIAL_REFRACTIVE);
  EXPECT_FLOAT_EQ(glass.ior, 1.5f);
  EXPECT_FLOAT_EQ(material({{"isrefractive", true}, {"ior", 1.3}}).ior, 1.3f);

  const Material lamp = material({{"type", "emissive"}, {"colour", {1.0, 0.5, 1.0}}, {"intensity", 4}});
  expect_vec3(lamp.emission, glm::vec3(4, 2, 4));
  expect_vec3(lamp.diffuse, glm::vec3(0));
  expect_vec3(material({{"type", "emissive"}, {"color", {1, 1, 1}}, {"intensity", 2}}).emission, glm::vec3(2));
  expect_vec3(material({{"emissioncolor", {0.5, 0.1, 0.1}}}).emission, glm::vec3(0.5f, 0.1f, 0.1f));
  expect_vec3(material({{"emission", {0.5, 0.1, 0.1}}}).emission, glm::vec3(0.5f, 0.1f, 0.1f));
  expect_vec3(material(json::object()).emission, glm::vec3(0));

  // Student files fill in refractiveindex 0 on opaque materials.
  EXPECT_FLOAT_EQ(material({{"refractiveindex", 0}}).ior, 1.0f);
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "sphere"}, {"center", {0, 0, 3}}, {"radius", 1},
                                                          {"material", {{"isrefractive", true}, {"refractiveindex", 0}}}})),
                       {"/scene/shapes/0/material/refractiveindex: expected a positive finite number, got 0"}));
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), {{"type", "sphere"}, {"center", {0, 0, 3}}, {"radius", 1},
                                                          {"material", {{"type", "plastic"}}}})),
                       {"/scene/shapes/0/material/type: expected a material type", "got \"plastic\""}));
}

TEST(FormatVariants, TextureSpellingsGiveTheSameTexture) {
  const std::string dir = test::temp_dir();
  write_file(dir, "textures/wood.ppm", tiny_ppm());
  const std::vector<json> spellings = {
      {{"material", {{"texture", "textures/wood.ppm"}}}},
      {{"material", {{"texture", "/home/student/cw/textures/wood.ppm"}}}},  // another machine's path
      {{"material", {{"texture_file", "textures/wood.ppm"}}}},
      {{"material", {{"texturefile", "C:\\Users\\me\\wood.ppm"}}}},
      {{"material", {{"textureFilename", "wood.ppm"}, {"hasTexture", true}}}},
      {{"material", {{"texturepath", "textures/wood.ppm"}, {"hastexture", true}}}},
      {{"texture", "wood.ppm"}},  // on the shape
  };
  json j = base_scene();
  for (const json& extra : spellings) {
    json shape = kSphere;
    shape.update(extra);
    j = with_shape(j, shape);
  }
  const Loaded l = parse(j, dir);
  EXPECT_TRUE(l.warnings.empty()) << l.warnings.front();
  ASSERT_EQ(l.scene.textures.size(), 1u);
  ASSERT_EQ(l.scene.materials.size(), 1u);
  EXPECT_EQ(l.scene.materials[0].texture, 0);
  EXPECT_EQ(l.scene.textures[0].kind, TEXTURE_IMAGE);
  EXPECT_EQ(l.scene.textures[0].width, 2u);

  // hasTexture false switches the path off; the texture is part of the
  // material's identity.
  j = with_shape(base_scene(), kSphere);
  json off = kSphere;
  off["material"] = {{"textureFilename", "wood.ppm"}, {"hasTexture", false}};
  j = with_shape(j, off);
  json on = kSphere;
  on["material"] = {{"texture", "wood.ppm"}};
  j = with_shape(j, on);
  const Loaded two = parse(j, dir);
  ASSERT_EQ(two.scene.materials.size(), 2u);
  EXPECT_EQ(two.scene.spheres[0].material, two.scene.spheres[1].material);
  EXPECT_NE(two.scene.spheres[0].material, two.scene.spheres[2].material);

  // A missing texture is a warning and a visible fallback, not an error.
  json missing = kSphere;
  missing["material"] = {{"texture", "nowhere.ppm"}};
  const Loaded m = parse(with_shape(with_shape(base_scene(), missing), missing), dir);
  ASSERT_EQ(m.warnings.size(), 1u);  // once per file, however many shapes use it
  EXPECT_TRUE(Contains(m.warnings[0], {"x.json: /scene/shapes/0/material/texture: warning", "nowhere.ppm"}));
  EXPECT_GE(m.scene.materials[0].texture, 0);
}

TEST(FormatVariants, CheckerboardTexture) {
  json shape = kSphere;
  shape["material"] = {{"texture", {{"type", "checkerboard"}, {"color1", {0.5, 1, 0.5}}, {"color2", {0.2, 0.4, 0.2}},
                                    {"scale", 10.0}}}};
  const Loaded l = parse(with_shape(with_shape(base_scene(), shape), shape));
  ASSERT_EQ(l.scene.textures.size(), 1u);  // the same checker once
  const Texture& t = l.scene.textures[0];
  EXPECT_EQ(t.kind, TEXTURE_CHECKER);
  expect_vec3(t.color1, glm::vec3(0.5f, 1, 0.5f));
  expect_vec3(t.color2, glm::vec3(0.2f, 0.4f, 0.2f));
  EXPECT_FLOAT_EQ(t.scale, 10.0f);
  shape["material"]["texture"] = {{"type", "marble"}};
  EXPECT_TRUE(Contains(error_of(with_shape(base_scene(), shape)),
                       {"/scene/shapes/0/material/texture/type: expected a procedural texture type"}));
}

// ---------------------------------------------------------------- unknown keys

TEST(FormatVariants, UnknownKeysWarnOnceOrFailWhenStrict) {
  json j = base_scene();
  for (int i = 0; i < 3; ++i) {
    json s = kSphere;
    s["material"] = {{"shininess", 3}};
    j = with_shape(j, s);
  }
  j["camera"]["zoom"] = 2;
  j["nsamples"] = 100;           // known, ignored: silent
  j["shadow samples"] = 8;       // known, ignored: silent
  j["_comment"] = "a comment";   // comments: silent
  const Loaded l = parse(j);
  ASSERT_EQ(l.warnings.size(), 2u);
  EXPECT_TRUE(Contains(l.warnings[0], {"x.json: /camera/zoom: warning: unknown key \"zoom\" ignored"}));
  EXPECT_TRUE(Contains(l.warnings[1], {"x.json: /scene/shapes/0/material/shininess: warning: unknown key",
                                       "(and 2 more like it)"}));

  EXPECT_TRUE(Contains(error_of(j, ".", /*strict=*/true),
                       {"x.json: /camera/zoom: expected one of the keys \"type\"", "strict", "got \"zoom\""}));
  j["camera"].erase("zoom");
  EXPECT_TRUE(Contains(error_of(j, ".", true), {"x.json: /scene/shapes/0/material/shininess: expected one of the keys"}));
  for (auto& s : j["scene"]["shapes"]) s.erase("material");
  EXPECT_TRUE(parse(j, ".", true).warnings.empty());  // known-but-ignored keys pass strict mode too
}

}  // namespace
}  // namespace caustica
