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
// [0.1, 0.4] and [0.6, 0.9]: one texel each. With `textured`, one material
// reads both from the texture; without, each quad has its own material
// with the texel's values as factors.
std::string floor_file(const Texels& t, bool textured) {
  Doc d;
  const std::vector<float> pos = {-1, 0, -1, -1, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, -1, 0, 0, 1, 1, 0, 1, 1, 0, -1};
  const std::vector<float> uv = {0.1f, 0, 0.1f, 1, 0.4f, 1, 0.4f, 0, 0.6f, 0, 0.6f, 1, 0.9f, 1, 0.9f, 0};
  const std::vector<uint16_t> left = {0, 1, 2, 0, 2, 3}, right = {4, 5, 6, 4, 6, 7};
  const int p = d.floats(pos, "VEC3", 3), u = d.floats(uv, "VEC2", 2);
  auto prim = [&](const std::vector<uint16_t>& idx, int material) {
    return json{{"attributes", {{"POSITION", p}, {"TEXCOORD_0", u}}},
                {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
                {"material", material}};
  };
  const json base = {0.8, 0.6, 0.3, 1.0};
  if (textured) {
    d.j["images"] = {{{"bufferView", d.view(ppm(t))}, {"mimeType", "image/png"}}};
    d.j["textures"] = {{{"source", 0}}};
    d.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", base},
                                                   {"metallicRoughnessTexture", {{"index", 0}}}}}}};
    d.j["meshes"] = {{{"primitives", {prim(left, 0), prim(right, 0)}}}};
  } else {
    auto constant = [&](int g, int b) {
      return json{{"pbrMetallicRoughness",
                   {{"baseColorFactor", base}, {"roughnessFactor", g / 255.0}, {"metallicFactor", b / 255.0}}}};
    };
    d.j["materials"] = {constant(t.g_a, t.b_a), constant(t.g_b, t.b_b)};
    d.j["meshes"] = {{{"primitives", {prim(left, 0), prim(right, 1)}}}};
  }
  d.node({{"mesh", 0}});
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
  const int w = textured.image.width;
  // Columns clear of the seam (x = 0 is the image's centre column).
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

}  // namespace
}  // namespace caustica
