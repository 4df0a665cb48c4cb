// glTF 2.0 import, analytically (host/scene/gltf*.cpp): files built here in
// memory with an embedded base64 buffer, so every expected value is known.
// Node transforms (TRS and matrices, composed parent * child), accessor
// strides and offsets, index types, triangle strips and fans, the winding
// under a mirroring transform, the camera from yfov and aspectRatio, the
// material and light mappings (scenes/FORMAT.md, "glTF 2.0 files"), and the
// errors: each names the file and the JSON pointer, and graphs that would
// hang or overflow a recursive walk are refused.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

#include "host/error.h"
#include "host/lights/light_types.h"
#include "host/render/render_state.h"
#include "host/scene/gltf.h"
#include "host/scene/load_scene.h"
#include "tests/support/gltf_doc.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;

using test::Doc;

constexpr double kPi = 3.14159265358979323846;

const std::vector<float> kTriangle = {1, 0, 0, 0, 1, 0, 0, 0, 1};

GltfModel import(const std::string& text) {
  static Scene scene;
  static TextureLibrary textures(scene);
  return import_gltf_bytes("t.gltf", text, ".", textures, /*allow_files=*/false);
}

void expect_near(const glm::vec3& got, const glm::vec3& want, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5f) << what << " component " << c;
}

TEST(Gltf, TrsComposesTranslateRotateScaleAndParentsApplyAfterChildren) {
  Doc d;
  const int m = d.mesh(kTriangle);
  // Child: scale 2, then 90 degrees about z, then translate (1, 2, 3).
  const double h = std::sqrt(0.5);
  d.node({{"children", {1}}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}});  // column-major: +10 x
  d.node({{"mesh", m}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}});
  const GltfModel g = import(d.text());
  ASSERT_EQ(g.mesh.triangles.size(), 1u);
  // (1,0,0) -> S (2,0,0) -> Rz90 (0,2,0) -> T (1,4,3) -> parent (11,4,3).
  expect_near(g.mesh.triangles[0].p[0], {11, 4, 3}, "v0");
  expect_near(g.mesh.triangles[0].p[1], {9, 2, 3}, "v1");   // (0,1,0) -> (0,2,0) -> (-2,0,0) -> (-1,2,3)
  expect_near(g.mesh.triangles[0].p[2], {11, 2, 5}, "v2");  // (0,0,1) -> (0,0,2) -> same -> (1,2,5)
}

TEST(Gltf, InterleavedAccessorsHonourStrideAndOffsets) {
  Doc d;
  // Three vertices of position (3 floats), normal (3), uv (2): stride 32.
  std::vector<float> v = {0, 0, 0, 0, 0, 1, 0.25f, 0.5f,  //
                          2, 0, 0, 0, 0, 1, 1, 0.5f,      //
                          0, 2, 0, 0, 0, 1, 0.25f, 0};
  const int view = d.view(Doc::bytes(v), 32);
  const int pos = d.accessor(view, 5126, 3, "VEC3", 0);
  const int nor = d.accessor(view, 5126, 3, "VEC3", 12);
  const int uv = d.accessor(view, 5126, 3, "VEC2", 24);
  // Unsigned byte indices after two bytes of padding inside their view.
  const std::vector<uint8_t> idx = {9, 9, 0, 1, 2};
  const int ind = d.accessor(d.view(Doc::bytes(idx)), 5121, 3, "SCALAR", 2);
  json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nor}, {"TEXCOORD_0", uv}}}, {"indices", ind}};
  d.j["meshes"] = json::array({{{"primitives", json::array({prim})}}});
  d.node({{"mesh", 0}});
  const GltfModel g = import(d.text());
  ASSERT_EQ(g.mesh.triangles.size(), 1u);
  const MeshTriangle& t = g.mesh.triangles[0];
  expect_near(t.p[1], {2, 0, 0}, "position 1");
  ASSERT_TRUE(t.has_normals && t.has_uvs);
  expect_near(t.n[2], {0, 0, 1}, "normal 2");
  // glTF's v counts down from the image's top, ours up from its bottom.
  EXPECT_FLOAT_EQ(t.uv[1].x, 1.0f);
  EXPECT_FLOAT_EQ(t.uv[1].y, 0.5f);
  EXPECT_FLOAT_EQ(t.uv[2].y, 1.0f);
}

TEST(Gltf, StripsAndFansKeepTheirWindingAndMirrorsSwapIt) {
  for (int mode : {5, 6}) {
    Doc d;
    // A unit square in z = 0, counter-clockwise seen from +z, as a strip
    // (0,1,3,2 order) or a fan around vertex 0.
    const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const std::vector<float> fan = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    d.mesh(mode == 5 ? strip : fan, {}, mode);
    d.node({{"mesh", 0}});
    const std::string text = d.text();
    const GltfModel g = import(text);
    ASSERT_EQ(g.mesh.triangles.size(), 2u) << "mode " << mode;
    for (const MeshTriangle& t : g.mesh.triangles)
      EXPECT_GT(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]).z, 0.0f) << "mode " << mode;
    // Mirrored in x (as a whole scene is loaded): still facing +z.
    Scene scene;
    TextureLibrary textures(scene);
    const glm::dmat4 mirror(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0),
                            glm::dvec4(0, 0, 0, 1));
    const GltfModel m = import_gltf_bytes("t.gltf", text, ".", textures, false, mirror);
    for (const MeshTriangle& t : m.mesh.triangles) {
      EXPECT_GT(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]).z, 0.0f) << "mirrored, mode " << mode;
      EXPECT_LE(t.p[0].x, 0.0f);
    }
  }
}

std::string error_of_text(const std::string& text) {
  return test::error_of([&] { import(text); });
}

TEST(Gltf, AccessorAndIndexErrorsNameTheirPointer) {
  {
    Doc d;
    d.mesh(kTriangle, {0, 1, 3});
    d.node({{"mesh", 0}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()),
                               {"t.gltf: /accessors/1: element 2 is index 3, out of range: the primitive has 3 vertices",
                                "/meshes/0/primitives/0/indices"}));
  }
  {
    Doc d;
    d.mesh(kTriangle);
    d.j["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte view
    d.node({{"mesh", 0}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /accessors/0: expected 4 elements of 12 bytes",
                                                         "to fit in /bufferViews/0 (36 bytes)"}));
  }
  {
    Doc d;
    d.mesh(kTriangle);
    d.j["bufferViews"][0]["byteLength"] = 4000;  // beyond the 36-byte buffer
    d.node({{"mesh", 0}});
    const std::string e = error_of_text(d.text());
    EXPECT_TRUE(test::Contains(e, {"t.gltf: ", "/bufferViews/0"})) << e;
  }
  {
    Doc d;
    d.mesh({1, 0, 0, 0, NAN, 0, 0, 0, 1});
    d.node({{"mesh", 0}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /accessors/0: element 1 is not finite",
                                                         "/meshes/0/primitives/0/attributes/POSITION"}));
  }
  {
    Doc d;
    d.mesh(kTriangle);
    d.j["accessors"][0].erase("bufferView");
    d.j["accessors"][0]["count"] = uint64_t(1) << 40;  // all zeros, but far too many
    d.node({{"mesh", 0}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /accessors/0/count: expected at most"}));
  }
  // Issue 38: an index past an int wrapped to a valid one; a string where
  // a number belongs loaded as the default.
  {
    Doc d;
    d.mesh(kTriangle);
    d.node({{"mesh", (uint64_t(1) << 32) + 1}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()),
                               {"t.gltf: /nodes/0/mesh: expected an index (an integer from 0 to 2147483647)"}));
  }
  {
    Doc d;
    d.mesh(kTriangle);
    d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = (uint64_t(1) << 32);
    d.node({{"mesh", 0}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"/attributes/POSITION: expected an accessor index"}));
  }
  for (const char* key : {"translation", "rotation", "scale", "matrix"}) {
    Doc d;
    d.mesh(kTriangle);
    const size_t n = std::string(key) == "matrix" ? 16 : std::string(key) == "rotation" ? 4 : 3;
    nlohmann::json values = nlohmann::json::array();
    for (size_t i = 0; i < n; ++i) values.push_back(i == 1 ? nlohmann::json("NaN") : nlohmann::json(1.0));
    d.node({{"mesh", 0}, {key, values}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()),
                               {"t.gltf: /nodes/0/" + std::string(key) + "/1: expected a number", "\"NaN\""}))
        << key << ": " << error_of_text(d.text());
  }
}

// Issue 38: a .glb header of another version or length, an empty scenes
// array, and JSON that does not parse (an Infinity literal, a number past
// a double) are refused in our words, with the line and column.
TEST(Gltf, GlbHeadersEmptyScenesAndJsonErrorsAreRefusedPrecisely) {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}});
  std::string json = d.text();
  while (json.size() % 4) json += ' ';
  auto glb = [&](uint32_t version, int length_delta) {
    std::string b = "glTF";
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) b += char((v >> (8 * i)) & 0xff);
    };
    u32(version);
    u32(uint32_t(12 + 8 + json.size() + length_delta));
    u32(uint32_t(json.size()));
    b += "JSON" + json;
    return b;
  };
  EXPECT_NO_THROW(import(glb(2, 0)));
  EXPECT_TRUE(test::Contains(error_of_text(glb(3, 0)), {"t.gltf: a binary glTF (.glb) header of version 3"}));
  EXPECT_TRUE(test::Contains(error_of_text(glb(2, 1)), {"header gives a length of", "the file has"}));
  Doc empty;
  empty.mesh(kTriangle);
  empty.node({{"mesh", 0}});
  empty.j["scenes"] = nlohmann::json::array();
  EXPECT_TRUE(test::Contains(error_of_text(empty.text()), {"t.gltf: /scenes: expected at least one scene"}));
  std::string infinity = d.text();
  infinity.replace(infinity.find('{'), 1, "{\n  \"x\": Infinity,");
  const std::string e = error_of_text(infinity);
  EXPECT_TRUE(test::Contains(e, {"t.gltf:2:", "JSON syntax error"})) << e;
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  std::string overflow = d.text();
  overflow.replace(overflow.find('{'), 1, "{\"extras\": {\"big\": 1e400},");
  const std::string o = error_of_text(overflow);
  EXPECT_TRUE(test::Contains(o, {"t.gltf:1:", "/extras/big: expected a finite number, got 1e400"})) << o;
}

TEST(Gltf, CyclesDeepChainsAndSharedChildrenAreRefusedWithoutRecursion) {
  {
    Doc d;
    d.mesh(kTriangle);
    d.node({{"children", {0}}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /nodes/0/children/0: node 0 is its own ancestor"}));
  }
  {
    Doc d;  // a chain deeper than the limit: an error, not a stack overflow
    for (int i = 0; i < 5000; ++i) d.node({{"children", {i + 1}}});
    d.node({{"mesh", d.mesh(kTriangle)}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /nodes/", "nested deeper than"}));
  }
  {
    Doc d;  // 40 levels of two references to the next node: 2^40 instances
    for (int i = 0; i < 40; ++i) d.node({{"children", {i + 1, i + 1}}});
    d.node({{"mesh", d.mesh(kTriangle)}});
    EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"node instances (the limit"}));
  }
}

// tinygltf 2.7 passes an image's buffer view to the image loader without
// checking it against its buffer (fuzz_gltf found the read past the end):
// the importer reads such images itself, with the check.
TEST(Gltf, AnImageViewBeyondItsBufferIsAnErrorNotARead) {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}});
  const int v = d.view(std::string(8, 'x'));
  d.j["bufferViews"][v]["byteLength"] = 4096;
  d.j["images"] = {{{"bufferView", v}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  d.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  EXPECT_TRUE(test::Contains(error_of_text(d.text()), {"t.gltf: /bufferViews/1: expected byteOffset + byteLength within "
                                                       "/buffers/0", "(the image /images/0)"}));
}

// tinygltf converts "extras" recursively: nesting is bounded before it runs.
TEST(Gltf, DeeplyNestedJsonIsRefusedEvenInExtras) {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}});
  std::string text = d.text();
  text.insert(text.size() - 1, R"(, "extras": )" + std::string(100000, '[') + std::string(100000, ']'));
  EXPECT_TRUE(test::Contains(error_of_text(text), {"t.gltf: /extras/0/0/0", "nested at most 64 levels"}));
}

TEST(Gltf, MaterialsMapOntoOursAsFormatMdSays) {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}});
  d.j["materials"] = json::array(
      {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}}, {"metallicFactor", 0.3},
                                  {"roughnessFactor", 0.5}}},
        {"doubleSided", true}},
       {{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                        {"KHR_materials_ior", {{"ior", 1.33}}}}}},
       {{"emissiveFactor", {17, 12, 4}}, {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2}}}}}},
       {{"extensions", {{"KHR_materials_pbrSpecularGlossiness",
                         {{"diffuseFactor", {0.2, 0.3, 0.4, 1}}, {"specularFactor", {0, 0, 0}}, {"glossinessFactor", 0.75}}}}}}});
  const GltfModel g = import(d.text());
  ASSERT_EQ(g.materials.size(), 4u);
  const Material& plastic = g.materials[0];
  expect_near(to_vec3(plastic.diffuse), {0.5f, 0.25f, 1}, "base colour");
  EXPECT_FLOAT_EQ(plastic.metallic, 0.3f);
  EXPECT_FLOAT_EQ(plastic.roughness, 0.25f);  // GGX alpha = roughness^2
  EXPECT_NEAR(plastic.specular.w, 0.04f, 1e-6f);  // F0 of index 1.5
  EXPECT_TRUE(plastic.flags & MATERIAL_TWO_SIDED);
  const Material& glass = g.materials[1];
  EXPECT_TRUE(glass.flags & MATERIAL_REFRACTIVE);
  EXPECT_NEAR(glass.ior, 1.33f, 1e-6f);
  expect_near(to_vec3(g.materials[2].emission), {34, 24, 8}, "emission beyond [0, 1] times strength");
  const Material& sg = g.materials[3];
  expect_near(to_vec3(sg.diffuse), {0.2f, 0.3f, 0.4f}, "spec-gloss diffuse");
  expect_near(to_vec3(sg.specular), {0, 0, 0}, "spec-gloss specular");
  EXPECT_FLOAT_EQ(sg.roughness, 0.0625f);
}

std::string camera_file() {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}});
  d.node({{"camera", 0}, {"translation", {0, 0, 5}}});
  d.node({{"camera", 1}, {"translation", {0, 0, 9}}});
  d.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"aspectRatio", 2.0}, {"znear", 0.1}}}},
                    {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}};
  return d.text({0, 1, 2});
}

TEST(Gltf, CamerasFromYfovAndAspectAndTheCameraOption) {
  const std::string path = test::write_scene("cams.gltf", camera_file());
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(path, o);
  EXPECT_NEAR(s.camera.fov_y_degrees, 0.5 * 180.0 / M_PI, 1e-4);
  EXPECT_EQ(s.camera.width, 800);
  EXPECT_EQ(s.camera.height, 400);
  expect_near(s.camera.position, {0, 0, 5}, "camera 0 position");
  expect_near(s.camera.look_at - s.camera.position, {0, 0, -1}, "camera 0 looks along -z");
  o.gltf_camera = 1;
  const Scene s1 = load_scene(path, o);
  expect_near(s1.camera.position, {0, 0, 9}, "camera 1 position");
  EXPECT_EQ(s1.camera.height, 600);  // no aspectRatio: 4:3
  // A render state of one camera's view is not resumed from another's.
  EXPECT_NE(scene_hash(s), scene_hash(s1));
  o.gltf_camera = 2;
  EXPECT_TRUE(test::Contains(test::error_of([&] { load_scene(path, o); }), {"--camera 2: ", "has 2 cameras (0 to 1)"}));
}

TEST(Gltf, NoCameraFramesTheBoundsAndNoLightMeansAWhiteSky) {
  Doc d;
  d.mesh({-1, -1, 0, 1, -1, 0, 1, 1, 0});
  d.node({{"mesh", 0}, {"translation", {0, 0, -3}}});
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(test::write_scene("nocam.glb.gltf", d.text()), o);
  // Bounds (-1,-1,-3)..(1,1,-3): centre (0,0,-3), radius sqrt(2); distance radius / sin(22.5 deg).
  expect_near(s.camera.look_at, {0, 0, -3}, "looks at the centre");
  expect_near(s.camera.position, {0, 0, float(-3 + std::sqrt(2.0) / std::sin(M_PI / 8))}, "from +z");
  expect_near(s.background, {1, 1, 1}, "white sky");
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(test::Contains(all, {"no camera", "no lights and no emissive materials"}));
}

TEST(Gltf, PunctualLightsMapToPointSpotAndDirectional) {
  Doc d;
  d.mesh({-1, -1, 0, 1, -1, 0, 1, 1, 0});
  d.node({{"mesh", 0}});
  d.node({{"translation", {2, 3, 4}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  // Turned 60 degrees about y: -z becomes (-sin 60, 0, -cos 60).
  d.node({{"rotation", {0, 0.5, 0, std::sqrt(0.75)}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  d.j["extensionsUsed"] = {"KHR_lights_punctual"};
  d.j["extensions"] = {{"KHR_lights_punctual",
                        {{"lights",
                          {{{"type", "point"}, {"color", {1, 0.5, 0}}, {"intensity", 10}},
                           {{"type", "spot"}, {"intensity", 3}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
                           {{"type", "directional"}, {"color", {1, 0.5, 0.25}}, {"intensity", 2}}}}}}};
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(test::write_scene("lights.gltf", d.text({0, 1, 2, 3})), o);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].kind, uint32_t(LIGHT_POINT));
  expect_near(to_vec3(s.lights[0].p0), {-2, 3, 4}, "point light, mirrored in x");
  expect_near(to_vec3(s.lights[0].emitted), {10, 5, 0}, "colour x intensity");
  EXPECT_EQ(s.lights[1].kind, uint32_t(LIGHT_SPOT));
  expect_near(to_vec3(s.lights[1].p1), {0, 0, -1}, "spot axis: the node's -z");
  EXPECT_NEAR(s.lights[1].p1.w, std::cos(0.4), 1e-6);
  EXPECT_NEAR(s.lights[1].p2.x, std::cos(0.2), 1e-6);
  // Directional: travelling along the node's -z, mirrored in x; colour x
  // intensity is its irradiance. No stand-in, so no warning.
  EXPECT_EQ(s.lights[2].kind, uint32_t(LIGHT_DIRECTIONAL));
  expect_near(to_vec3(s.lights[2].p1), {float(std::sqrt(0.75)), 0, -0.5f}, "directional: the node's -z, mirrored");
  expect_near(to_vec3(s.lights[2].emitted), {2, 1, 0.5f}, "directional: colour x intensity");
  for (const std::string& w : warnings) EXPECT_EQ(w.find("directional"), std::string::npos) << w;
}

// A glTF file's sun renders as the directional light it is: a Lambertian
// plane (base colour 0.5, metallic 0, KHR_materials_ior 1: no specular
// layer) seen from above by the file's camera, under a directional light
// 60 degrees from the plane's normal of colour x intensity (1, 2, 4) x 1.5,
// shows (0.5 / pi) E cos 60 at every pixel (exact: a delta light).
TEST(Gltf, DirectionalLightLightsAPlaneWithItsIrradiance) {
  Doc d;
  // The plane y = 0, wound to face +y, 20 wide.
  d.mesh({-10, 0, -10, -10, 0, 10, 10, 0, 10, -10, 0, -10, 10, 0, 10, 10, 0, -10});
  d.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0},
                                                 {"roughnessFactor", 1}}},
                       {"extensions", {{"KHR_materials_ior", {{"ior", 1.0}}}}}}};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  d.j["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_ior"};
  d.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"aspectRatio", 1.0}, {"znear", 0.01}}}}};
  d.j["extensions"] = {{"KHR_lights_punctual",
                        {{"lights", {{{"type", "directional"}, {"color", {1, 2, 4}}, {"intensity", 1.5}}}}}}};
  const double h = std::sqrt(0.5);
  d.node({{"mesh", 0}});
  // The camera 5 above, looking down (-z turned -90 degrees about x).
  d.node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", {-h, 0, 0, h}}});
  // The light: -z turned -30 degrees about x, travelling down at 60 degrees
  // from -y: (0, -sin 30, -cos 30).
  d.node({{"rotation", {-std::sin(kPi / 12), 0, 0, std::cos(kPi / 12)}},
          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  const std::string path = test::write_scene("sun.gltf", d.text({0, 1, 2}));
  const Scene s = load_scene(path);
  ASSERT_EQ(s.lights.size(), 1u);
  expect_near(to_vec3(s.lights[0].p1), {0, -0.5f, -float(std::sqrt(0.75))}, "the light's direction");
  test::CameraRenderOptions o;
  o.spp = 2;
  o.size = 16;
  const test::CameraRender r = test::render_with_camera(path, RenderMode::Path, o);
  const glm::dvec3 e = 1.5 * glm::dvec3(1, 2, 4);
  for (int py = 0; py < r.image.height; ++py)
    for (int px = 0; px < r.image.width; ++px)
      for (int c = 0; c < 3; ++c) {
        const double expected = 0.5 / kPi * e[c] * 0.5;
        ASSERT_NEAR(r.image.at(px, py)[c], expected, 1e-4 * expected) << "pixel " << px << ", " << py << ", channel " << c;
      }
}

TEST(Gltf, ACourseworkSceneCanPlaceAGltfMeshWithATransform) {
  Doc d;
  d.mesh(kTriangle);
  d.node({{"mesh", 0}, {"translation", {0, 0, 1}}});
  d.j["materials"] = {{{"emissiveFactor", {2, 2, 2}}}};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  test::write_scene("part.gltf", d.text());
  const std::string scene = test::write_scene("placed.json", R"({"camera": {"width": 8, "height": 8,
    "position": [0, 0, -10], "lookAt": [0, 0, 0], "upVector": [0, 1, 0], "fov": 40},
    "scene": {"shapes": [{"type": "mesh", "file": "part.gltf", "transform": {"translate": [5, 0, 0], "scale": 2}}]}})");
  const Scene s = load_scene(scene);
  ASSERT_EQ(s.triangles.size(), 1u);
  // File: (1,0,0) + (0,0,1) = (1,0,1); shape: x2 then +5 x: (7, 0, 2).
  expect_near(to_vec3(s.triangles[0].v0), {7, 0, 2}, "v0");
  expect_near(to_vec3(s.materials[s.triangles[0].material].emission), {2, 2, 2}, "the file's material");
}

// The repository's example (tools/make_gltf_example.py) loads with its
// camera, both lights (the sun a directional light) and every material,
// without a warning.
TEST(Gltf, TheExampleSceneLoadsWhole) {
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(test::source_dir() + "/scenes/gltf_example.gltf", o);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  EXPECT_EQ(s.mode, RenderMode::Path);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].kind, uint32_t(LIGHT_DIRECTIONAL));
  EXPECT_EQ(s.camera.width, 800);
  EXPECT_EQ(s.camera.height, 533);
  EXPECT_EQ(s.textures.size(), 1u);  // the embedded checker
  bool glass = false, gold = false, lamp = false;
  for (const Material& m : s.materials) {
    glass |= (m.flags & MATERIAL_REFRACTIVE) != 0;
    gold |= m.metallic == 1.0f;
    lamp |= m.emission.x == 6.0f && (m.flags & MATERIAL_TWO_SIDED);
  }
  EXPECT_TRUE(glass && gold && lamp);
}

}  // namespace
}  // namespace caustica
