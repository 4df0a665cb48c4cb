// glTF's data textures per texel (issue 24): a metallicRoughnessTexture is
// stored linear (the 8-bit codes, not sRGB-decoded) as the material's
// roughness_texture and sampled where the kernels build the BSDF
// (kernels/lib/material.h). Checked three ways: the import (texel values,
// no warning), the host's caster/receiver classification (judged at the
// texture's extremes, conservatively), and a render: a floor whose two
// halves read two different texels must look like the same floor made of
// two constant materials with those values, within noise.
#include <gtest/gtest.h>

#include <glm/gtc/packing.hpp>

#include <cmath>

#include "host/scene/features.h"
#include "host/scene/gltf.h"
#include "host/scene/load_scene.h"
#include "host/scene/textures.h"
#include "tests/support/gltf_doc.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;
using test::Doc;

// Two texel values (G = roughness, B = metallic, codes 0..255), each over
// four columns of an 8 x 1 binary PPM: bilinear filtering reads texel A
// alone for u in [1/16, 7/16] and B alone for u in [9/16, 15/16].
struct Texels {
  int g_a, b_a, g_b, b_b;
};
std::string ppm(const Texels& t) {
  std::string s = "P6 8 1 255\n";
  for (int i = 0; i < 8; ++i) {
    s += char(0);
    s += char(i < 4 ? t.g_a : t.g_b);
    s += char(i < 4 ? t.b_a : t.b_b);
  }
  return s;
}

// A 2 x 2 floor in y = 0 made of two quads, x < 0 and x > 0, whose u covers
// [0.1, 0.4] and [0.6, 0.9]: one texel each; the quads' materials are
// left_material and right_material. Adds the mesh and its node to d.
// With `colours` (8 x 4 bytes), a COLOR_0 of normalized unsigned bytes.
void add_floor(Doc& d, int left_material, int right_material, const std::vector<uint8_t>& colours = {}) {
  const std::vector<float> pos = {-1, 0, -1, -1, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, -1, 0, 0, 1, 1, 0, 1, 1, 0, -1};
  const std::vector<float> uv = {0.1f, 0, 0.1f, 1, 0.4f, 1, 0.4f, 0, 0.6f, 0, 0.6f, 1, 0.9f, 1, 0.9f, 0};
  const std::vector<uint16_t> left = {0, 1, 2, 0, 2, 3}, right = {4, 5, 6, 4, 6, 7};
  const int p = d.floats(pos, "VEC3", 3), u = d.floats(uv, "VEC2", 2);
  json attributes = {{"POSITION", p}, {"TEXCOORD_0", u}};
  if (!colours.empty()) {
    attributes["COLOR_0"] = d.accessor(d.view(Doc::bytes(colours)), 5121, 8, "VEC4");
    d.j["accessors"].back()["normalized"] = true;
  }
  auto prim = [&](const std::vector<uint16_t>& idx, int material) {
    return json{{"attributes", attributes},
                {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
                {"material", material}};
  };
  d.j["meshes"] = {{{"primitives", {prim(left, left_material), prim(right, right_material)}}}};
  d.node({{"mesh", 0}});
}

// The floor with `textured`: one material reads both quads' values from
// the texture; without: each quad has its own material with the texel's
// values as factors.
std::string floor_file(const Texels& t, bool textured) {
  Doc d;
  const json base = {0.8, 0.6, 0.3, 1.0};
  if (textured) {
    d.j["images"] = {{{"bufferView", d.view(ppm(t))}, {"mimeType", "image/png"}}};
    d.j["textures"] = {{{"source", 0}}};
    d.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", base},
                                                   {"metallicRoughnessTexture", {{"index", 0}}}}}}};
    add_floor(d, 0, 0);
  } else {
    auto constant = [&](int g, int b) {
      return json{{"pbrMetallicRoughness",
                   {{"baseColorFactor", base}, {"roughnessFactor", g / 255.0}, {"metallicFactor", b / 255.0}}}};
    };
    d.j["materials"] = {constant(t.g_a, t.b_a), constant(t.g_b, t.b_b)};
    add_floor(d, 0, 1);
  }
  return d.text();
}

// The floor under a point light and a dim sky, seen from above and in
// front, in path mode.
std::string floor_scene(const std::string& name, const std::string& gltf) {
  test::write_scene(name + ".gltf", gltf);
  return test::write_scene(name + ".json", R"({"rendermode": "pathtracer", "nbounces": 4,
    "camera": {"width": 32, "height": 16, "position": [0, 1.6, 2.2], "lookAt": [0, 0, 0], "upVector": [0, 1, 0],
               "fov": 40},
    "scene": {"backgroundcolor": [0.2, 0.25, 0.3],
      "lightsources": [{"type": "pointlight", "position": [0.3, 1.5, 0.8], "intensity": [3, 3, 3]}],
      "shapes": [{"type": "mesh", "file": ")" + name + R"(.gltf"}]}})");
}

const Texels kRoughPlasticAndGlossyMetal = {204, 0, 77, 255};

TEST(GltfTextures, MetallicRoughnessTexelsAreStoredLinearAndSampledWithoutAWarning) {
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(floor_scene("mr_import", floor_file(kRoughPlasticAndGlossyMetal, true)), o);
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(s.materials.size(), 1u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.texture, -1);
  ASSERT_GE(m.roughness_texture, 0);
  EXPECT_FLOAT_EQ(m.roughness, 1.0f);  // the factors, 1 by default
  EXPECT_FLOAT_EQ(m.metallic, 1.0f);
  const Texture& tex = s.textures[size_t(m.roughness_texture)];
  ASSERT_EQ(tex.kind, TEXTURE_IMAGE);
  ASSERT_EQ(tex.width * tex.height, 8u);
  auto texel = [&](int i, int c) { return glm::unpackHalf1x16(s.texels[(tex.offset + size_t(i)) * 4 + size_t(c)]); };
  // The codes / 255 (sRGB decoding would give 0.604 and 0.0742).
  EXPECT_NEAR(texel(0, 1), 204 / 255.0, 1e-3);
  EXPECT_NEAR(texel(7, 1), 77 / 255.0, 1e-3);
  EXPECT_NEAR(texel(7, 2), 1.0, 1e-3);
  EXPECT_NEAR(texel(0, 2), 0.0, 1e-6);
}

// One image as both a colour and a data texture: two textures, the colour
// one sRGB-decoded, the data one as stored.
TEST(GltfTextures, AnImageUsedForColourAndDataIsStoredBothWays) {
  Doc d;
  d.mesh({1, 0, 0, 0, 1, 0, 0, 0, 1});
  d.node({{"mesh", 0}});
  d.j["images"] = {{{"bufferView", d.view(ppm({204, 0, 77, 255}))}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  d.j["materials"] = {{{"pbrMetallicRoughness",
                        {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}}}};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  Scene scene;
  TextureLibrary textures(scene);
  const GltfModel g = import_gltf_bytes("both.gltf", d.text(), ".", textures, /*allow_files=*/false);
  ASSERT_EQ(g.materials.size(), 1u);
  const Material& m = g.materials[0];
  ASSERT_GE(m.texture, 0);
  ASSERT_GE(m.roughness_texture, 0);
  ASSERT_NE(m.texture, m.roughness_texture);
  auto g_of = [&](int t) { return glm::unpackHalf1x16(scene.texels[size_t(scene.textures[size_t(t)].offset) * 4 + 1]); };
  EXPECT_NEAR(g_of(m.texture), srgb_byte_to_linear(204), 1e-3);
  EXPECT_NEAR(g_of(m.roughness_texture), 204 / 255.0, 1e-3);
}

// A sampler's wrap modes and filter, and KHR_texture_transform, become the
// texture record's sampling (lib/texture.h), the transform carried into
// this format's uv (v up); a use without them reads the same texels
// plainly; bad values are errors naming their pointer.
Doc sampled_doc(const json& sampler, const json& transform) {
  Doc d;
  d.mesh({1, 0, 0, 0, 1, 0, 0, 0, 1});
  d.node({{"mesh", 0}});
  d.j["extensionsUsed"] = {"KHR_texture_transform"};
  d.j["images"] = {{{"bufferView", d.view(ppm({204, 0, 77, 255}))}, {"mimeType", "image/png"}}};
  d.j["samplers"] = {sampler};
  d.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  d.j["materials"] = {{{"pbrMetallicRoughness",
                        {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}}}},
                       {"emissiveFactor", {1, 1, 1}},
                       {"emissiveTexture", {{"index", 0}}}}};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  return d;
}

TEST(GltfTextures, SamplersAndTextureTransformsBecomeTheRecordsSampling) {
  const double pi = 3.14159265358979;
  Doc d = sampled_doc({{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}},
                      {{"offset", {0.25, 0.5}}, {"rotation", pi / 2}, {"scale", {2.0, 3.0}}});
  Scene scene;
  TextureLibrary textures(scene);
  const GltfModel g = import_gltf_bytes("sampled.gltf", d.text(), ".", textures, /*allow_files=*/false);
  for (const std::string& w : g.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  const Material& m = g.materials[0];
  ASSERT_GE(m.texture, 0);
  ASSERT_GE(m.emission_texture, 0);
  const Texture& t = scene.textures[size_t(m.texture)];
  const Texture& plain = scene.textures[size_t(m.emission_texture)];
  EXPECT_EQ(t.sampling, TEXTURE_CLAMP_U | TEXTURE_MIRROR_V | TEXTURE_NEAREST | TEXTURE_TRANSFORMED);
  EXPECT_EQ(plain.sampling, TEXTURE_CLAMP_U | TEXTURE_MIRROR_V | TEXTURE_NEAREST);  // the sampler, no transform
  EXPECT_EQ(t.offset, plain.offset);  // the same texels
  // A point of glTF's uv, (0.2, 0.3), maps to R S uv + offset with R =
  // [cos sin; -sin cos] at a quarter turn: (3 * 0.3 + 0.25, -2 * 0.2 +
  // 0.5) = (1.15, 0.1); in ours (v up) the point is (0.2, 0.7) and its
  // image (1.15, 0.9). (The direction is the extension's test model's:
  // docs/gltf.md.)
  const glm::vec3 u(t.uv_u.x, t.uv_u.y, t.uv_u.z), v(t.uv_v.x, t.uv_v.y, t.uv_v.z);
  const glm::vec3 ours(0.2f, 0.7f, 1.0f);
  EXPECT_NEAR(glm::dot(u, ours), 1.15f, 1e-6f);
  EXPECT_NEAR(glm::dot(v, ours), 0.9f, 1e-6f);
  // No transform and repeat: the decoded image as it is.
  Doc repeat = sampled_doc({{"wrapS", 10497}}, {{"offset", {0.0, 0.0}}});
  Scene scene2;
  TextureLibrary textures2(scene2);
  const GltfModel g2 = import_gltf_bytes("plain.gltf", repeat.text(), ".", textures2, false);
  EXPECT_EQ(g2.materials[0].texture, g2.materials[0].emission_texture);
  EXPECT_EQ(scene2.textures[size_t(g2.materials[0].texture)].sampling, 0u);
}

TEST(GltfTextures, BadSamplersAndTransformsNameTheirPointer) {
  auto error = [](Doc d) {
    return test::error_of([&] {
      Scene scene;
      TextureLibrary textures(scene);
      import_gltf_bytes("bad.gltf", d.text(), ".", textures, false);
    });
  };
  EXPECT_TRUE(test::Contains(error(sampled_doc({{"wrapS", 1234}}, json::object())),
                             {"bad.gltf: /samplers/0/wrapS: expected 10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648",
                              "got 1234"}));
  EXPECT_TRUE(test::Contains(error(sampled_doc(json::object(), {{"offset", {1.0}}})),
                             {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
                              "offset: expected an array of 2 finite numbers"}));
  EXPECT_TRUE(test::Contains(error(sampled_doc(json::object(), {{"texCoord", -1}})),
                             {"KHR_texture_transform/texCoord"}));
}

// The photon pass's split (host/scene/features.cpp): a material whose
// texture reaches a smooth metallic texel casts, one whose texture reaches
// a rough or dielectric texel receives; both at once here.
TEST(GltfTextures, CausticClassificationReadsTheTexturesExtremes) {
  const Scene both = load_scene(floor_scene("mr_both", floor_file(kRoughPlasticAndGlossyMetal, true)));
  EXPECT_TRUE(material_casts_caustics(both, both.materials[0]));
  EXPECT_TRUE(material_receives_caustics(both, both.materials[0]));
  EXPECT_TRUE(analyse_scene(both, RenderMode::Path).caustics) << "a caster and a receiver in one material";
  // Every texel rough (alpha = 0.8^2 and 0.7^2 > CAUSTIC_CASTER_ALPHA), metallic or not: a receiver only.
  const Scene rough = load_scene(floor_scene("mr_rough", floor_file({204, 255, 179, 0}, true)));
  EXPECT_FALSE(material_casts_caustics(rough, rough.materials[0]));
  EXPECT_TRUE(material_receives_caustics(rough, rough.materials[0]));
  // Every texel smooth metal: a caster only.
  const Scene metal = load_scene(floor_scene("mr_metal", floor_file({20, 255, 60, 255}, true)));
  EXPECT_TRUE(material_casts_caustics(metal, metal.materials[0]));
  EXPECT_FALSE(material_receives_caustics(metal, metal.materials[0]));
}

// Each half of the floor (columns clear of the seam: x = 0 is the image's
// centre column) has the same mean in both renders within 4 standard
// errors, and the two halves differ by far more (the texels matter).
void expect_halves_alike(const test::PathRender& textured, const test::PathRender& constant) {
  const int w = textured.image.width;
  auto left = [&](int x, int) { return x < w / 2 - 2; };
  auto right = [&](int x, int) { return x >= w / 2 + 2; };
  const test::Mean tl = test::mean_over(textured, left), tr = test::mean_over(textured, right);
  const test::Mean cl = test::mean_over(constant, left), cr = test::mean_over(constant, right);
  std::printf("left  textured %.5f +- %.5f  constant %.5f +- %.5f\n", tl.mean, tl.se, cl.mean, cl.se);
  std::printf("right textured %.5f +- %.5f  constant %.5f +- %.5f\n", tr.mean, tr.se, cr.mean, cr.se);
  EXPECT_NEAR(tl.mean, cl.mean, 4.0 * std::hypot(tl.se, cl.se));
  EXPECT_NEAR(tr.mean, cr.mean, 4.0 * std::hypot(tr.se, cr.se));
  EXPECT_GT(std::fabs(tl.mean - tr.mean), 10.0 * std::hypot(tl.se, tr.se)) << "the two texels look alike";
}

// The textured floor against two constant materials: each half's mean
// within 4 standard errors, and the halves far apart (the texture matters).
TEST(GltfTextures, APerTexelFloorRendersAsTwoConstantMaterials) {
  const int spp = int(test::sized(64, 8));
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;  // the same estimator on both sides
  const test::PathRender textured =
      test::render_path(floor_scene("mr_tex", floor_file(kRoughPlasticAndGlossyMetal, true)), spp, o);
  o.seed = 7;
  const test::PathRender constant =
      test::render_path(floor_scene("mr_const", floor_file(kRoughPlasticAndGlossyMetal, false)), spp, o);
  expect_halves_alike(textured, constant);
}

// glTF multiplies baseColorFactor by baseColorTexture (the coursework
// format's texture replaces the colour): the floor textured with two
// colour texels under a factor renders as two constant materials of factor
// x texel (sRGB-decoded), within noise.
std::string base_colour_floor(const Texels& t, bool textured) {
  Doc d;
  const glm::vec3 factor(0.9f, 0.5f, 0.7f);
  auto material = [&](glm::vec3 colour) {
    return json{{"pbrMetallicRoughness", {{"baseColorFactor", {colour.x, colour.y, colour.z, 1.0}},
                                          {"metallicFactor", 0.0}, {"roughnessFactor", 0.6}}}};
  };
  if (textured) {
    d.j["images"] = {{{"bufferView", d.view(ppm(t))}, {"mimeType", "image/png"}}};
    d.j["textures"] = {{{"source", 0}}};
    json m = material(factor);
    m["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    d.j["materials"] = {m};
    add_floor(d, 0, 0);
  } else {
    auto texel = [&](int g, int b) {
      return factor * glm::vec3(0.0f, srgb_byte_to_linear(uint8_t(g)), srgb_byte_to_linear(uint8_t(b)));
    };
    d.j["materials"] = {material(texel(t.g_a, t.b_a)), material(texel(t.g_b, t.b_b))};
    add_floor(d, 0, 1);
  }
  return d.text();
}

TEST(GltfTextures, BaseColourIsTheFactorTimesTheTexture) {
  const Texels texels = {230, 60, 40, 200};
  std::vector<std::string> warnings;
  LoadOptions lo;
  lo.warnings = &warnings;
  const Scene s = load_scene(floor_scene("bc_import", base_colour_floor(texels, true)), lo);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE(s.materials[0].flags & MATERIAL_TEXTURE_SCALES);
  const int spp = int(test::sized(64, 8));
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;
  const test::PathRender textured = test::render_path(floor_scene("bc_tex", base_colour_floor(texels, true)), spp, o);
  o.seed = 7;
  const test::PathRender constant =
      test::render_path(floor_scene("bc_const", base_colour_floor(texels, false)), spp, o);
  expect_halves_alike(textured, constant);
}

// A material whose textures name TEXCOORD_1 (by textureInfo.texCoord or
// by KHR_texture_transform's texCoord) has its primitives read TEXCOORD_1
// as their texture coordinates; textures naming two sets are warned and
// read with the smaller.
GltfModel two_uv_sets(const json& base_colour_info, const json& emissive_info = nullptr,
                      std::vector<std::string>* warnings = nullptr) {
  Doc d;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0}, uv0(6, 0.0f), uv1 = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  d.j["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", d.floats(pos, "VEC3", 3)},
                                                     {"TEXCOORD_0", d.floats(uv0, "VEC2", 2)},
                                                     {"TEXCOORD_1", d.floats(uv1, "VEC2", 2)}}},
                                     {"material", 0}}}}}};
  d.node({{"mesh", 0}});
  d.j["images"] = {{{"bufferView", d.view(ppm({204, 0, 77, 255}))}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  json material = {{"pbrMetallicRoughness", {{"baseColorTexture", base_colour_info}}}};
  if (!emissive_info.is_null()) {
    material["emissiveTexture"] = emissive_info;
    material["emissiveFactor"] = {1, 1, 1};
  }
  d.j["materials"] = {material};
  d.j["extensionsUsed"] = {"KHR_texture_transform"};
  Scene scene;
  TextureLibrary textures(scene);
  GltfModel g = import_gltf_bytes("uv.gltf", d.text(), ".", textures, false);
  if (warnings) *warnings = g.warnings;
  return g;
}

TEST(GltfTextures, AMaterialsTexturesReadTheCoordinateSetTheyName) {
  auto expect_uv1 = [](const GltfModel& g, const std::string& what) {
    ASSERT_EQ(g.mesh.triangles.size(), 1u) << what;
    const MeshTriangle& t = g.mesh.triangles[0];
    ASSERT_TRUE(t.has_uvs) << what;
    EXPECT_NEAR(t.uv[2].x, 0.5f, 1e-6f) << what;
    EXPECT_NEAR(t.uv[2].y, 1.0f - 0.6f, 1e-6f) << what;  // v up the image here
  };
  std::vector<std::string> warnings;
  expect_uv1(two_uv_sets({{"index", 0}, {"texCoord", 1}}, nullptr, &warnings), "textureInfo.texCoord");
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  expect_uv1(two_uv_sets({{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}),
             "KHR_texture_transform's texCoord");
  // Two sets in one material: the smaller, with a warning.
  const GltfModel mixed = two_uv_sets({{"index", 0}, {"texCoord", 1}}, {{"index", 0}}, &warnings);
  EXPECT_NEAR(mixed.mesh.triangles[0].uv[2].x, 0.0f, 1e-6f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(test::Contains(warnings[0], {"/materials/0", "2 texture coordinate sets", "TEXCOORD_0 is used"}));
}

// COLOR_0 multiplies the base colour (glTF 2.0, 3.7.2.1): a floor whose
// halves carry two vertex colours under one factor renders as two constant
// materials of factor x colour, within noise; the import reads them
// without a warning and the program gets them only where some mesh has them.
std::string vertex_colour_floor(bool coloured) {
  Doc d;
  const glm::vec3 factor(0.9f, 0.8f, 0.7f);
  const glm::ivec3 a(255, 64, 32), b(32, 128, 255);
  auto material = [&](glm::vec3 colour) {
    return json{{"pbrMetallicRoughness", {{"baseColorFactor", {colour.x, colour.y, colour.z, 1.0}},
                                          {"metallicFactor", 0.0}, {"roughnessFactor", 0.6}}}};
  };
  if (coloured) {
    std::vector<uint8_t> colours;
    for (int v = 0; v < 8; ++v) {
      const glm::ivec3 c = v < 4 ? a : b;
      colours.insert(colours.end(), {uint8_t(c.x), uint8_t(c.y), uint8_t(c.z), 255});
    }
    d.j["materials"] = {material(factor)};
    add_floor(d, 0, 0, colours);
  } else {
    d.j["materials"] = {material(factor * glm::vec3(a) / 255.0f), material(factor * glm::vec3(b) / 255.0f)};
    add_floor(d, 0, 1);
  }
  return d.text();
}

TEST(GltfTextures, VertexColoursMultiplyTheBaseColour) {
  std::vector<std::string> warnings;
  LoadOptions lo;
  lo.warnings = &warnings;
  const Scene s = load_scene(floor_scene("vc_import", vertex_colour_floor(true)), lo);
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(s.triangle_colours.size(), s.triangles.size());
  EXPECT_TRUE(analyse_scene(s, RenderMode::Path).vertex_colours);
  EXPECT_NEAR(glm::unpackHalf1x16(s.triangle_colours[0].rgba[1]), 64 / 255.0, 1e-3);
  const Scene plain = load_scene(floor_scene("vc_plain", vertex_colour_floor(false)));
  EXPECT_TRUE(plain.triangle_colours.empty());
  EXPECT_FALSE(analyse_scene(plain, RenderMode::Path).vertex_colours);
  const int spp = int(test::sized(64, 8));
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;
  const test::PathRender coloured = test::render_path(floor_scene("vc_col", vertex_colour_floor(true)), spp, o);
  o.seed = 7;
  const test::PathRender constant = test::render_path(floor_scene("vc_const", vertex_colour_floor(false)), spp, o);
  expect_halves_alike(coloured, constant);
}

}  // namespace
}  // namespace caustica
