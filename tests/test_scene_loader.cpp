// Scene loading: the official coursework files, camera basis convention,
// error messages for malformed input, and the Table-1 scene generator.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "host/error.h"
#include "host/scene/generate.h"
#include "host/scene/load_scene.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;

using test::Contains;

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = test::temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

using test::error_of;

std::string parse_error_of(const json& j) {
  return error_of([&] { parse_scene(j, "x.json", ".", {}); });
}

// A small valid scene; error tests break one thing in it.
json valid_scene() {
  return json::parse(R"({
    "nbounces": 3, "rendermode": "phong",
    "camera": {"type": "pinhole", "width": 64, "height": 32, "position": [0, 0, 0],
               "lookAt": [0, 0, 1], "upVector": [0, 1, 0], "fov": 45, "exposure": 0.1},
    "scene": {
      "backgroundcolor": [0.1, 0.2, 0.3],
      "lightsources": [{"type": "pointlight", "position": [0, 1, 0], "intensity": [0.5, 0.5, 0.5]}],
      "shapes": [
        {"type": "sphere", "center": [0, 0, 3], "radius": 0.5},
        {"type": "cylinder", "center": [1, 0, 3], "axis": [0, 2, 0], "radius": 0.2, "height": 0.3},
        {"type": "triangle", "v0": [0, 0, 2], "v1": [1, 0, 2], "v2": [0, 1, 2]},
        {"type": "sphere", "center": [0, 0, 5], "radius": 1}
      ]}})");
}

json with(json j, const std::string& pointer, json value) {
  j[json::json_pointer(pointer)] = std::move(value);
  return j;
}

json without(json j, const std::string& pointer) {
  const json::json_pointer p(pointer);
  j[p.parent_pointer()].erase(p.back());
  return j;
}

// ---------------------------------------------------------------- official scenes

void expect_official_scenes(const std::string& dir) {
  const Scene s = load_scene(dir + "scene.json");
  EXPECT_EQ(s.mode, RenderMode::Binary);
  EXPECT_EQ(s.nbounces, 8);
  EXPECT_EQ(lights_of_kind(s, LIGHT_POINT).size(), 2u);
  EXPECT_EQ(s.spheres.size(), 3u);
  EXPECT_EQ(s.cylinders.size(), 1u);
  EXPECT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.background, glm::vec3(0.25f));
  EXPECT_EQ(s.camera.width, 1200);
  EXPECT_EQ(s.camera.height, 800);
  EXPECT_FLOAT_EQ(s.camera.fov_y_degrees, 45.0f);
  EXPECT_FLOAT_EQ(s.camera.exposure, 0.1f);
  EXPECT_EQ(s.camera.position, glm::vec3(0.0f, 0.75f, -0.25f));
  EXPECT_EQ(to_vec3(s.cylinders[0].axis_half), glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(s.cylinders[0].axis_half.w, 0.2f);
  EXPECT_FLOAT_EQ(s.cylinders[0].center_radius.w, 0.15f);
  EXPECT_FLOAT_EQ(s.spheres[0].center_radius.w, 25.1f);
  // ground, cylinder, the two triangles' shared one, red sphere, red mirror sphere
  EXPECT_EQ(s.materials.size(), 5u);
  EXPECT_EQ(s.triangles[0].material, s.triangles[1].material);
  EXPECT_NE(s.spheres[1].material, s.spheres[2].material);
  const Material& mirror = s.materials[s.spheres[2].material];
  EXPECT_EQ(mirror.flags, MATERIAL_REFLECTIVE);
  EXPECT_FLOAT_EQ(mirror.diffuse.x, 0.8f);
  EXPECT_FLOAT_EQ(mirror.diffuse.w, 0.9f);   // kd
  EXPECT_FLOAT_EQ(mirror.specular.w, 0.1f);  // ks
  EXPECT_FLOAT_EQ(mirror.ka, kDefaultAmbient);
  EXPECT_EQ(mirror.texture, -1);
  EXPECT_FLOAT_EQ(s.materials[s.spheres[0].material].specular_exponent, 10.0f);

  const Scene b = load_scene(dir + "binary_primitives.json");
  EXPECT_EQ(b.mode, RenderMode::Binary);
  EXPECT_EQ(b.nbounces, 4);  // absent: default
  EXPECT_TRUE(b.lights.empty());
  EXPECT_EQ(b.primitive_count(), 3u);
  EXPECT_EQ(to_vec3(b.cylinders[0].axis_half), glm::vec3(1, 0, 0));
  ASSERT_EQ(b.materials.size(), 1u);  // all default, deduplicated
  EXPECT_EQ(to_vec3(b.materials[0].diffuse), glm::vec3(0.8f));
  EXPECT_FLOAT_EQ(b.materials[0].specular_exponent, 20.0f);
  EXPECT_EQ(b.materials[0].flags, 0u);

  const Scene p = load_scene(dir + "simple_phong.json");
  EXPECT_EQ(p.mode, RenderMode::Phong);
  ASSERT_EQ(lights_of_kind(p, LIGHT_POINT).size(), 1u);
  EXPECT_EQ(to_vec3(p.lights[0].emitted), glm::vec3(0.75f));
  EXPECT_EQ(p.spheres.size(), 1u);
  EXPECT_EQ(p.cylinders.size(), 1u);
  EXPECT_EQ(p.triangles.size(), 2u);
  EXPECT_FLOAT_EQ(p.cylinders[0].axis_half.w, 0.5f);

  const Scene m = load_scene(dir + "mirror_image.json");
  EXPECT_EQ(m.spheres.size(), 2u);
  EXPECT_EQ(m.cylinders.size(), 1u);
  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.materials[m.triangles[0].material].flags, 0u);
  EXPECT_EQ(m.materials[m.triangles[3].material].flags, MATERIAL_REFLECTIVE);
}

TEST(SceneLoader, OfficialScenesFromShared) {
  CAUSTICA_REQUIRE_SHARED(shared);
  expect_official_scenes(shared + "/scenes-coursework/official/");
}

TEST(SceneLoader, OfficialScenesInRepository) { expect_official_scenes(test::source_dir() + "/scenes/"); }

// Student variants: every file either loads or fails with a readable Error.
TEST(SceneLoader, CommunityScenesLoadOrFailCleanly) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const auto dir = std::filesystem::path(shared) / "scenes-coursework" / "community";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no community scenes";
  LoadOptions options;
  std::vector<std::string> warnings;
  options.warnings = &warnings;
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    try {
      load_scene(entry.path().string(), options);
      ++loaded;
    } catch (const Error& e) {
      EXPECT_TRUE(Contains(e.what(), {entry.path().string()}));
    }
  }
  EXPECT_GT(loaded, 0);
}

// ---------------------------------------------------------------- camera basis

TEST(CameraBasis, PlusXIsOnTheRightLookingAlongPlusZ) {
  CameraDesc c;
  c.position = glm::vec3(0);
  c.look_at = glm::vec3(0, 0, 5);
  c.up = glm::vec3(0, 3, 0);  // length does not matter
  const CameraBasis b = camera_basis(c);
  EXPECT_EQ(b.forward, glm::vec3(0, 0, 1));
  EXPECT_EQ(b.right, glm::vec3(1, 0, 0));
  EXPECT_EQ(b.up, glm::vec3(0, 1, 0));
}

TEST(CameraBasis, OrthonormalForRandomInputs) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f);
  for (int i = 0; i < 1000; ++i) {
    CameraDesc c;
    c.position = {u(gen), u(gen), u(gen)};
    c.look_at = {u(gen), u(gen), u(gen)};
    c.up = {u(gen), u(gen), u(gen)};
    CameraBasis b;
    try {
      b = camera_basis(c);
    } catch (const Error&) {
      continue;  // (near-)parallel draws are rejected, which is the point
    }
    EXPECT_NEAR(glm::length(b.forward), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(b.right), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(b.up), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(b.forward, b.right), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(b.forward, b.up), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(b.right, b.up), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(b.forward, glm::normalize(c.look_at - c.position)), 0.0f, 1e-5f);
    EXPECT_GT(glm::dot(b.up, c.up), 0.0f);  // up' is on the same side as the given up
  }
}

TEST(CameraBasis, DegenerateInputsThrow) {
  CameraDesc c;
  c.position = c.look_at = glm::vec3(1, 2, 3);
  EXPECT_TRUE(Contains(error_of([&] { camera_basis(c); }), {"degenerate camera"}));
  c.look_at = glm::vec3(1, 5, 3);
  c.up = glm::vec3(0, -2, 0);
  EXPECT_TRUE(Contains(error_of([&] { camera_basis(c); }), {"parallel"}));
}

// ---------------------------------------------------------------- malformed input

TEST(SceneErrors, ValidBaseSceneLoads) {
  const Scene s = parse_scene(valid_scene(), "x.json", ".");
  EXPECT_EQ(s.primitive_count(), 4u);
  EXPECT_EQ(s.source_path, "x.json");
  EXPECT_NEAR(glm::length(to_vec3(s.cylinders[0].axis_half)), 1.0f, 1e-6f);  // [0,2,0] normalised
}

TEST(SceneErrors, FileProblems) {
  EXPECT_TRUE(Contains(error_of([] { load_scene("/no/such/dir/x.json"); }), {"/no/such/dir/x.json", "not found"}));
  const std::string dir = test::temp_dir();
  EXPECT_TRUE(Contains(error_of([&] { load_scene(dir); }), {dir, "directory"}));
  EXPECT_TRUE(Contains(error_of([] { load_scene(write_file("empty.json", "")); }), {"empty.json", "syntax error"}));
}

TEST(SceneErrors, UnreadableFile) {
  const std::string path = write_file("locked.json", valid_scene().dump());
  std::filesystem::permissions(path, std::filesystem::perms::none);
  if (std::ifstream(path)) GTEST_SKIP() << "running with permission to read any file (root)";
  EXPECT_TRUE(Contains(error_of([&] { load_scene(path); }), {path, "cannot open"}));
}

TEST(SceneErrors, SyntaxErrorReportsLineAndColumn) {
  const std::string path = write_file("bad.json", "{\n  \"nbounces\": 8,\n  \"camera\": ,\n}\n");
  const std::string msg = error_of([&] { load_scene(path); });
  EXPECT_TRUE(Contains(msg, {path + ":3:13: JSON syntax error", "unexpected ','"}));
  const std::string path2 = write_file("bad2.json", "{\"a\": [1, 2}");
  EXPECT_TRUE(Contains(error_of([&] { load_scene(path2); }), {path2 + ":1:12:"}));
}

TEST(SceneErrors, MessageFormat) {
  EXPECT_EQ(parse_error_of(with(valid_scene(), "/scene/shapes/3/radius", -0.5)),
            "x.json: /scene/shapes/3/radius: expected a positive finite number, got -0.5");
  EXPECT_EQ(parse_error_of(with(valid_scene(), "/camera/position", "abc")),
            "x.json: /camera/position: expected an array of 3 numbers, got \"abc\"");
}

TEST(SceneErrors, MissingRequiredKeys) {
  for (const char* pointer :
       {"/camera", "/scene", "/scene/shapes", "/camera/width", "/camera/height", "/camera/fov", "/camera/position",
        "/camera/lookAt", "/camera/upVector", "/scene/shapes/0/type", "/scene/shapes/0/radius",
        "/scene/shapes/0/center", "/scene/shapes/1/axis", "/scene/shapes/1/height", "/scene/shapes/2/v2",
        "/scene/lightsources/0/position", "/scene/lightsources/0/intensity", "/scene/lightsources/0/type"}) {
    EXPECT_TRUE(Contains(parse_error_of(without(valid_scene(), pointer)),
                         {std::string("x.json: ") + pointer + ": required key", "is missing (expected"}));
  }
}

TEST(SceneErrors, WrongTypes) {
  const json base = valid_scene();
  EXPECT_TRUE(Contains(parse_error_of(json::array()), {"x.json: /: expected an object, got []"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/position", json{1, 2})),
                       {"/camera/position: expected an array of 3 numbers, got [1,2]"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/lookAt/1", "x")),
                       {"/camera/lookAt/1: expected a finite number, got \"x\""}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/width", "1200")),
                       {"/camera/width: expected an integer in [1, 32768], got \"1200\""}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/height", 10.5)), {"/camera/height: expected an integer"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera", 3)), {"/camera: expected an object, got 3"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes", json::object())),
                       {"/scene/shapes: expected an array, got {}"}));
  EXPECT_TRUE(
      Contains(parse_error_of(with(base, "/scene/shapes/2", "triangle")), {"/scene/shapes/2: expected an object"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes/0/material", json::array())),
                       {"/scene/shapes/0/material: expected an object"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes/0/material/isreflective", "yes")),
                       {"/scene/shapes/0/material/isreflective: expected true or false, got \"yes\""}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes/0/material/diffusecolor", json{1, -1, 0})),
                       {"/scene/shapes/0/material/diffusecolor/1: expected a non-negative finite number, got -1"}));
  // Reflectances stop at 100 (issue 24: one of 1e29 blacked out the image); emission does not.
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes/0/material/ks", 101)),
                       {"/scene/shapes/0/material/ks: expected a reflectance in [0, 100]", "got 101"}));
  EXPECT_NO_THROW(parse_scene(with(base, "/scene/shapes/0/material/ks", 100), "x.json", ".", {}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/nbounces", -1)), {"/nbounces: expected an integer in [0, "}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/rendermode", 1)), {"/rendermode: expected a string, got 1"}));
}

TEST(SceneErrors, NonFiniteNumbers) {
  // nlohmann refuses to parse an out-of-range literal; the loader still names the key.
  std::string text = valid_scene().dump();
  text.replace(text.find("\"radius\":0.5"), 12, "\"radius\":1e999");
  const std::string inf_file = write_file("inf.json", text);
  EXPECT_TRUE(Contains(error_of([&] { load_scene(inf_file); }),
                       {inf_file + ":1:", ": /scene/shapes/0/radius: expected a finite number, got 1e999"}));
  text = valid_scene().dump();
  text.replace(text.find("\"position\":[0,0,0]"), 18, "\"position\":[0,-1e999,0]");
  const std::string inf_file2 = write_file("inf2.json", text);
  EXPECT_TRUE(Contains(error_of([&] { load_scene(inf_file2); }), {": /camera/position/1: expected a finite number"}));

  // Documents built in memory can hold inf and nan.
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/scene/shapes/0/radius", inf)),
                       {"/scene/shapes/0/radius: expected a positive finite number, got inf"}));
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/camera/position/1", -inf)),
                       {"/camera/position/1: expected a finite number, got -inf"}));
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/camera/exposure", std::nan(""))),
                       {"/camera/exposure: expected a finite number, got nan"}));
  // Finite in double, infinite once stored as float.
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/scene/shapes/2/v0/0", 1e39)),
                       {"/scene/shapes/2/v0/0: expected a finite number within single precision", "got 1e+39"}));
}

TEST(SceneErrors, OutOfRangeValues) {
  const json base = valid_scene();
  EXPECT_TRUE(
      Contains(parse_error_of(with(base, "/scene/shapes/0/radius", 0)), {"/scene/shapes/0/radius", "positive"}));
  EXPECT_TRUE(
      Contains(parse_error_of(with(base, "/scene/shapes/1/radius", -1)), {"/scene/shapes/1/radius", "positive"}));
  EXPECT_TRUE(
      Contains(parse_error_of(with(base, "/scene/shapes/1/height", 0)), {"/scene/shapes/1/height", "positive"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/scene/shapes/1/axis", json{0, 0, 0})),
                       {"/scene/shapes/1/axis: expected a direction of nonzero length, got [0,0,0]"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/width", 0)), {"/camera/width: expected an integer in [1,"}));
  EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/height", -5)), {"/camera/height", "got -5"}));
  for (double fov : {0.0, -10.0, 180.0, 200.0})
    EXPECT_TRUE(Contains(parse_error_of(with(base, "/camera/fov", fov)), {"/camera/fov", "0 < fov < 180"}));
}

TEST(SceneErrors, DegenerateCamera) {
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/camera/lookAt", json{0, 0, 0})),
                       {"x.json: /camera: degenerate camera", "lookAt equals position"}));
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/camera/upVector", json{0, 0, -3})),
                       {"x.json: /camera: degenerate camera", "parallel"}));
}

TEST(SceneErrors, UnknownTypesListTheSupportedOnes) {
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/scene/shapes/2/type", "torus")),
                       {"/scene/shapes/2/type: expected", "\"sphere\"", "\"cylinder\"", "\"triangle\"", "\"mesh\"",
                        "got \"torus\""}));
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/rendermode", "raytrace")),
                       {"/rendermode: expected one of \"binary\", \"phong\", \"pathtracer\"", "got \"raytrace\""}));
  EXPECT_TRUE(Contains(parse_error_of(with(valid_scene(), "/scene/lightsources/0/type", "searchlight")),
                       {"/scene/lightsources/0/type: expected", "\"pointlight\"", "\"arealight\"", "\"spotlight\"", "got \"searchlight\""}));
}

TEST(SceneModes, DefaultsPathTracingAndOverride) {
  EXPECT_EQ(parse_scene(without(valid_scene(), "/rendermode"), "x.json", ".").mode, RenderMode::Phong);
  EXPECT_EQ(parse_scene(without(valid_scene(), "/nbounces"), "x.json", ".").nbounces, 4);
  EXPECT_EQ(parse_scene(with(valid_scene(), "/rendermode", "binary"), "x.json", ".").mode, RenderMode::Binary);
  for (const char* name : {"pathtracer", "pathtracing", "path"})
    EXPECT_EQ(parse_scene(with(valid_scene(), "/rendermode", name), "x.json", ".").mode, RenderMode::Path);
}

// A lens camera type without an aperture, and an area light without a size,
// are rendered (as a pinhole camera, as a small square) but said so.
TEST(SceneWarnings, DroppedTrianglesVariantCamerasAndAreaLights) {
  json j = with(valid_scene(), "/scene/shapes/2/v2", json{2, 0, 2});  // collinear with v0, v1
  j = with(j, "/camera/type", "finiteAperture");
  j = with(j, "/scene/lightsources/0/type", "arealight");
  std::vector<std::string> warnings;
  LoadOptions options;
  options.warnings = &warnings;
  const Scene s = parse_scene(j, "x.json", ".", options);
  EXPECT_EQ(s.triangles.size(), 0u);
  EXPECT_EQ(s.spheres.size(), 2u);
  EXPECT_EQ(lights_of_kind(s, LIGHT_POINT).size(), 0u);
  EXPECT_EQ(lights_of_kind(s, LIGHT_RECT).size(), 1u);
  EXPECT_EQ(whitted_lights(s).size(), 1u);  // phong's stand-in
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_TRUE(Contains(warnings[0], {"x.json: /camera/type: warning", "finiteAperture", "pinhole"}));
  EXPECT_TRUE(Contains(warnings[1], {"x.json: /scene/lightsources/0: warning", "area light"}));
  EXPECT_TRUE(Contains(warnings[2], {"x.json: /scene/shapes/2: warning", "zero area"}));
  // Without a sink, warnings go to stderr.
  ::testing::internal::CaptureStderr();
  parse_scene(with(valid_scene(), "/scene/shapes/2/v1", json{0, 0, 2}), "x.json", ".");
  EXPECT_TRUE(Contains(::testing::internal::GetCapturedStderr(), {"/scene/shapes/2: warning"}));
}

// The triangle of valid_scene() faces +z, away from the camera at the
// origin: as a one-sided emitter it lights nothing the camera sees.
TEST(SceneWarnings, EmitterFacingAwayFromTheCamera) {
  auto warnings_of = [](const json& j) {
    std::vector<std::string> warnings;
    LoadOptions options;
    options.warnings = &warnings;
    parse_scene(j, "x.json", ".", options);
    return warnings;
  };
  const json emissive = with(valid_scene(), "/scene/shapes/2/material", json{{"emission", {1, 1, 1}}});
  const auto away = warnings_of(emissive);
  ASSERT_EQ(away.size(), 1u);
  EXPECT_TRUE(Contains(away[0], {"x.json: /scene/shapes/2: warning", "faces away from the camera", "twosided"}));
  json toward = with(emissive, "/scene/shapes/2/v1", json{0, 1, 2});
  toward = with(toward, "/scene/shapes/2/v2", json{1, 0, 2});
  EXPECT_TRUE(warnings_of(toward).empty());
  EXPECT_TRUE(warnings_of(with(emissive, "/scene/shapes/2/material/twosided", true)).empty());
  EXPECT_TRUE(warnings_of(valid_scene()).empty());  // not emissive
  const json rect = with(valid_scene(), "/scene/shapes/2",
                         json{{"type", "rectangle"}, {"v0", {0, 0, 2}}, {"v1", {1, 0, 2}}, {"v2", {1, 1, 2}},
                              {"v3", {0, 1, 2}}, {"material", {{"emission", {1, 1, 1}}}}});
  EXPECT_EQ(warnings_of(rect).size(), 1u);
}

TEST(SceneWarnings, ManyDroppedTrianglesAreSummarised) {
  json j = valid_scene();
  for (int i = 0; i < 20; ++i)
    j["scene"]["shapes"].push_back({{"type", "triangle"}, {"v0", {i, 0, 1}}, {"v1", {i, 0, 1}}, {"v2", {0, 1, 1}}});
  std::vector<std::string> warnings;
  LoadOptions options;
  options.warnings = &warnings;
  EXPECT_EQ(parse_scene(j, "x.json", ".", options).triangles.size(), 1u);
  ASSERT_EQ(warnings.size(), 9u);  // the first 8, then the total
  EXPECT_TRUE(Contains(warnings[0], {"/scene/shapes/4: warning"}));
  EXPECT_TRUE(Contains(warnings[8], {"/scene/shapes: warning: 20 zero-area triangles dropped"}));
}

TEST(SceneMaterials, DefaultsPerKeyAndDeduplication) {
  json j = valid_scene();
  j["scene"]["shapes"][0]["material"] = {{"kd", 0.5}, {"isreflective", true}, {"ka", 0.1}};
  j["scene"]["shapes"][3]["material"] = {{"ka", 0.1}, {"isreflective", true}, {"kd", 0.5}};  // same, reordered
  const Scene s = parse_scene(j, "x.json", ".");
  ASSERT_EQ(s.materials.size(), 2u);  // that one + the default shared by cylinder and triangle
  EXPECT_EQ(s.spheres[0].material, s.spheres[1].material);
  EXPECT_EQ(s.cylinders[0].material, s.triangles[0].material);
  const Material& m = s.materials[s.spheres[0].material];
  EXPECT_EQ(to_vec3(m.diffuse), glm::vec3(0.8f));
  EXPECT_FLOAT_EQ(m.diffuse.w, 0.5f);
  EXPECT_EQ(to_vec3(m.specular), glm::vec3(1.0f));
  EXPECT_FLOAT_EQ(m.specular.w, 0.1f);
  EXPECT_FLOAT_EQ(m.specular_exponent, 20.0f);
  EXPECT_FLOAT_EQ(m.reflectivity, 1.0f);
  EXPECT_FLOAT_EQ(m.ior, 1.0f);
  EXPECT_FLOAT_EQ(m.ka, 0.1f);
  EXPECT_EQ(m.flags, MATERIAL_REFLECTIVE);
  EXPECT_FLOAT_EQ(s.materials[s.cylinders[0].material].ka, kDefaultAmbient);
}

// ---------------------------------------------------------------- Table-1 generator

TEST(Table1Generator, DeterministicAndPinned) {
  const std::string a = generate_table1_scene(400, false, 1).dump();
  EXPECT_EQ(a, generate_table1_scene(400, false, 1).dump());
  EXPECT_NE(a, generate_table1_scene(400, false, 2).dump());
  // FNV-1a of the text: the same bytes on every platform. Changing the
  // generator on purpose means updating this value.
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : a) h = (h ^ c) * 1099511628211ull;
  EXPECT_EQ(h, 12924222566426168160ull) << a.substr(0, 600);
}

TEST(Table1Generator, CountsPerTypeAndLoads) {
  struct Case {
    int count;
    bool mixed;
    size_t spheres, cylinders, triangles;
  };
  for (const Case& c : {Case{400, false, 400, 0, 0}, Case{1600, true, 534, 533, 533},
                        Case{6400, true, 2134, 2133, 2133}, Case{12800, true, 4268, 4266, 4266}}) {
    const json j = generate_table1_scene(c.count, c.mixed, 1);
    EXPECT_EQ(j["scene"]["shapes"].size(), static_cast<size_t>(c.count));
    std::vector<std::string> warnings;
    LoadOptions options;
    options.warnings = &warnings;
    const Scene s = parse_scene(j, table1_scene_name(c.count, c.mixed) + ".json", ".", options);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(s.spheres.size(), c.spheres) << c.count;
    EXPECT_EQ(s.cylinders.size(), c.cylinders) << c.count;
    EXPECT_EQ(s.triangles.size(), c.triangles) << c.count;
    EXPECT_EQ(s.mode, RenderMode::Phong);
    EXPECT_EQ(s.camera.width, 1200);
    EXPECT_EQ(s.camera.height, 800);
    EXPECT_GE(s.light_count(), 1u);
    EXPECT_LE(s.materials.size(), 17u);  // palette x {matte, mirror} + ground, deduplicated
    bool any_mirror = false;
    for (const Material& m : s.materials) any_mirror |= (m.flags & MATERIAL_REFLECTIVE) != 0;
    EXPECT_TRUE(any_mirror);
  }
  EXPECT_EQ(table1_scene_name(400, false), "400_spheres");
  EXPECT_EQ(table1_scene_name(12800, true), "12800_shapes");
  EXPECT_TRUE(Contains(error_of([] { generate_table1_scene(0, true, 1); }), {"shape_count"}));
}

TEST(Table1Generator, ObjectsShrinkWithCount) {
  auto mean_radius = [](int count) {
    const Scene s = parse_scene(generate_table1_scene(count, false, 3), "g.json", ".");
    double sum = 0;
    for (size_t i = 1; i < s.spheres.size(); ++i) sum += s.spheres[i].center_radius.w;  // [0] is the ground
    return sum / static_cast<double>(s.spheres.size() - 1);
  };
  // 8x the count: half the size (count^-1/3), within sampling noise.
  EXPECT_NEAR(mean_radius(3200) / mean_radius(400), 0.5, 0.05);
}

}  // namespace
}  // namespace caustica
