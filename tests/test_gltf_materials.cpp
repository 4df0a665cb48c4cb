// glTF's layered and transmissive materials (issue 43):
// KHR_materials_clearcoat, tinted and partial KHR_materials_transmission,
// KHR_materials_volume's absorption and KHR_materials_specular, mapped as
// scenes/FORMAT.md says (host/scene/gltf_materials.cpp) onto lib/bsdf.h
// and lib/material.h. The BSDFs themselves are checked on the host
// (tests/host/test_bsdf.cpp: chi-square, sampling against evaluation,
// albedo <= 1); here the mapping and renders whose answer is exact:
// light seen through glass of index 1 (no refraction, no reflection) is
// the emitter's times the tint at each crossing times exp(-sigma length);
// a sheet transmitting a share t shows t of what lies behind it; a white
// Lambertian under a smooth coat reflects a white sky exactly.
#include <gtest/gtest.h>

#include <cmath>

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

GltfModel import(const json& material, std::vector<std::string>* warnings = nullptr) {
  Doc d;
  d.mesh({1, 0, 0, 0, 1, 0, 0, 0, 1});
  d.node({{"mesh", 0}});
  d.j["materials"] = {material};
  d.j["meshes"][0]["primitives"][0]["material"] = 0;
  // One texture for the extensions' textureInfos to name.
  d.j["images"] = {{{"bufferView", d.view(std::string("P6 1 1 255\n\x80\x80\xff", 14))}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  static Scene scene;
  static TextureLibrary textures(scene);
  GltfModel g = import_gltf_bytes("m.gltf", d.text(), ".", textures, false);
  if (warnings) *warnings = g.warnings;
  return g;
}

TEST(GltfMaterials, ExtensionsBecomeTheMaterialsNumbers) {
  std::vector<std::string> warnings;
  // Clear coat: weight and alpha = roughness^2, its textures as data, its
  // own normal map with its scale.
  const Material coat = import({{"extensions", {{"KHR_materials_clearcoat",
                                                 {{"clearcoatFactor", 0.8}, {"clearcoatRoughnessFactor", 0.3},
                                                  {"clearcoatTexture", {{"index", 0}}},
                                                  {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}}}}},
                               &warnings)
                            .materials[0];
  EXPECT_FLOAT_EQ(coat.clearcoat, 0.8f);
  EXPECT_FLOAT_EQ(coat.clearcoat_alpha, 0.09f);
  EXPECT_GE(coat.clearcoat_texture, 0);
  EXPECT_GE(coat.clearcoat_normal_texture, 0);
  EXPECT_FLOAT_EQ(coat.clearcoat_normal_scale, 0.5f);
  // This triangle has no texture coordinates: the one warning says so.
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(test::Contains(warnings[0], {"without TEXCOORD_0; the normal map is ignored there"}));

  // Transmission 0.6 of a half-metallic material: glass 0.6 x 0.5 = 0.3 of
  // the time, the opaque base (metallic 0.5 / 0.7) otherwise; tinted.
  const Material t = import({{"pbrMetallicRoughness", {{"metallicFactor", 0.5}}},
                             {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.6}}}}}})
                         .materials[0];
  EXPECT_TRUE(t.flags & MATERIAL_REFRACTIVE);
  EXPECT_TRUE(t.flags & MATERIAL_TINTED_TRANSMISSION);
  EXPECT_NEAR(t.volume.w, 0.7f, 1e-6f);
  EXPECT_NEAR(t.metallic, 0.5f / 0.7f, 1e-6f);
  EXPECT_FALSE(t.flags & MATERIAL_ATTENUATES);

  // Volume: sigma = -ln(c) / d; no thickness: a thin wall, no absorption.
  json volume = {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                 {"KHR_materials_volume",
                  {{"thicknessFactor", 1.0}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 1.0, 0.25}}}}};
  const json dielectric = {{"metallicFactor", 0.0}};  // glTF's default, 1, is a metal: no glass at all
  const Material v = import({{"pbrMetallicRoughness", dielectric}, {"extensions", volume}}).materials[0];
  EXPECT_TRUE(v.flags & MATERIAL_ATTENUATES);
  EXPECT_NEAR(v.volume.x, std::log(2.0) / 2.0, 1e-6);
  EXPECT_EQ(v.volume.y, 0.0f);
  EXPECT_NEAR(v.volume.z, std::log(4.0) / 2.0, 1e-6);
  EXPECT_EQ(v.volume.w, 0.0f);
  volume["KHR_materials_volume"]["thicknessFactor"] = 0.0;
  EXPECT_FALSE(import({{"pbrMetallicRoughness", dielectric}, {"extensions", volume}}).materials[0].flags &
               MATERIAL_ATTENUATES);
  // Transmission on a metal (the default metallicFactor) is no glass, and says so.
  const GltfModel metal = import({{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}},
                                 &warnings);
  EXPECT_EQ(metal.materials[0].volume.w, 1.0f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(test::Contains(warnings[0], {"/materials/0/extensions/KHR_materials_transmission",
                                           "metallicFactor 1 (glTF's default)", "no glass"}));

  // Specular: F0 = min(0.04 x colour, 1) x factor, as colour x strength.
  const Material s = import({{"extensions", {{"KHR_materials_specular",
                                              {{"specularFactor", 0.5}, {"specularColorFactor", {2.0, 1.0, 0.5}}}}}}})
                         .materials[0];
  EXPECT_NEAR(s.specular.w * s.specular.x, 0.04f, 1e-6f);
  EXPECT_NEAR(s.specular.w * s.specular.y, 0.02f, 1e-6f);
  EXPECT_NEAR(s.specular.w * s.specular.z, 0.01f, 1e-6f);

  // Out of range: an error naming the pointer.
  EXPECT_TRUE(test::Contains(
      test::error_of([] {
        import({{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.5}}}}}});
      }),
      {"m.gltf: /materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor: expected a number in [0, 1]"}));
  EXPECT_TRUE(test::Contains(
      test::error_of([] {
        import({{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 2}}}}}});
      }),
      {"/materials/0/extensions/KHR_materials_transmission/transmissionFactor: expected a number in [0, 1]"}));
}

// The square x, z in [-half, half] at height y, facing +y (or -y when
// `down`), as a primitive of `material`.
json square(Doc& d, float y, float half, int material, bool down = false) {
  const std::vector<float> pos = {-half, y, -half, -half, y, half, half, y, half, half, y, -half};
  const std::vector<float> uv = {0, 0, 0, 1, 1, 1, 1, 0};  // u = (x + half) / (2 half)
  const std::vector<uint16_t> up_idx = {0, 1, 2, 0, 2, 3}, down_idx = {0, 2, 1, 0, 3, 2};
  const std::vector<uint16_t>& idx = down ? down_idx : up_idx;
  return json{{"attributes", {{"POSITION", d.floats(pos, "VEC3", 3)}, {"TEXCOORD_0", d.floats(uv, "VEC2", 2)}}},
              {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
              {"material", material}};
}

// A closed box x, z in [-1, 1], y in [y0, y1], outward faces, of `material`.
json box(Doc& d, float y0, float y1, int material) {
  std::vector<float> pos;
  for (int i = 0; i < 8; ++i) pos.insert(pos.end(), {i & 1 ? 1.0f : -1.0f, i & 2 ? y1 : y0, i & 4 ? 1.0f : -1.0f});
  const std::vector<uint16_t> idx = {0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1,
                                     4, 5, 7, 4, 7, 6, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return json{{"attributes", {{"POSITION", d.floats(pos, "VEC3", 3)}}},
              {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
              {"material", material}};
}

// Seen from straight above; no lights but what the file emits; black sky
// unless `sky`.
std::string overhead(const std::string& name, const std::string& gltf, double sky = 0.0) {
  test::write_scene(name + ".gltf", gltf);
  const std::string s = std::to_string(sky);
  return test::write_scene(name + ".json", R"({"rendermode": "pathtracer", "nbounces": 8,
    "camera": {"width": 16, "height": 16, "position": [0, 5, 0], "lookAt": [0, 0, 0], "upVector": [0, 0, -1],
               "fov": 20},
    "scene": {"backgroundcolor": [)" + s + ", " + s + ", " + s + R"(], "lightsources": [],
      "shapes": [{"type": "mesh", "file": ")" + name + R"(.gltf"}]}})");
}

const json kEmitter = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
                       {"emissiveFactor", {1, 1, 1}},
                       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}}}};

// Glass of index 1 neither bends nor reflects: the emitter seen through a
// box of it is 2 x tint^2 (two crossings) x exp(-sigma x 1).
TEST(GltfMaterials, LightThroughATintedAbsorbingBoxIsTintedTwiceAndAttenuatedByBeerLambert) {
  Doc d;
  const json glass = {{"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.8, 1.0, 0.9, 1}}, {"roughnessFactor", 0.0}, {"metallicFactor", 0.0}}},
                      {"extensions",
                       {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                        {"KHR_materials_ior", {{"ior", 1.0}}},
                        {"KHR_materials_volume",
                         {{"thicknessFactor", 1.0}, {"attenuationDistance", 0.5},
                          {"attenuationColor", {0.5, 0.25, 1.0}}}}}}};
  d.j["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                           "KHR_materials_emissive_strength"};
  d.j["materials"] = {kEmitter, glass};
  d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 4.0f, 0), box(d, 0.5f, 1.5f, 1)}}}};
  d.node({{"mesh", 0}});
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;  // nothing here to gather, and the same estimator everywhere
  const test::PathRender r = test::render_path(overhead("volume_box", d.text()), 4, o);
  // exp(-sigma L) = c^(L / 0.5) over the length L = 1 / cos(theta) a
  // pixel's ray runs inside (theta its lean from the vertical).
  const double tint2[3] = {0.64, 1.0, 0.81}, colour[3] = {0.5, 0.25, 1.0};
  const double slope = std::tan(10.0 * 3.14159265358979 / 180.0) / 8.0;  // per pixel from the centre
  for (int y = 5; y < 11; ++y)
    for (int x = 5; x < 11; ++x) {
      const double dx = (x + 0.5 - 8.0) * slope, dy = (y + 0.5 - 8.0) * slope;
      const double length = std::sqrt(1.0 + dx * dx + dy * dy);
      for (int c = 0; c < 3; ++c) {
        const double want = 2.0 * tint2[c] * std::pow(colour[c], length / 0.5);
        EXPECT_NEAR(r.image.at(x, y)[c], want, 1e-3 * want) << "pixel " << x << ", " << y << " channel " << c;
      }
    }
}

// A single sheet of index 1 transmitting a share t = 0.35 over a white
// Lambertian (F0 = 0 at index 1), with the emitter below and a black sky
// above: the sheet's glass shows the emitter, its opaque base (lit only
// from below, its back) shows black, so the mean is t x 2.
TEST(GltfMaterials, APartlyTransmissiveSheetShowsItsShareOfWhatLiesBehind) {
  Doc d;
  const json sheet = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"roughnessFactor", 0.0},
                                                {"metallicFactor", 0.0}}},
                      {"extensions",
                       {{"KHR_materials_transmission", {{"transmissionFactor", 0.35}}},
                        {"KHR_materials_ior", {{"ior", 1.0}}}}}};
  d.j["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength"};
  d.j["materials"] = {kEmitter, sheet};
  d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 4.0f, 0), square(d, 1.0f, 2.0f, 1)}}}};
  d.node({{"mesh", 0}});
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;
  const test::PathRender r = test::render_path(overhead("partial_sheet", d.text()), int(test::sized(256, 32)), o);
  const test::Mean m = test::mean_all(r);
  std::printf("partial transmission: %.5f +- %.5f, expected %.5f\n", m.mean, m.se, 0.35 * 2.0);
  EXPECT_NEAR(m.mean, 0.35 * 2.0, 4.0 * m.se);
  EXPECT_LT(m.se, 0.01);
}

// The white furnace under a clear coat: a white Lambertian (index 1: no
// layer of its own) under a smooth coat of weight 1 reflects (1 - Fc) x 1
// + Fc x 1 = 1 of a white sky; under a rough coat no more than 1, and
// less only by GGX's single-scattering loss (a few percent at most here).
TEST(GltfMaterials, ACoatedWhiteLambertianInAWhiteFurnace) {
  for (double roughness : {0.0, 0.5}) {
    Doc d;
    const json coated = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0.0}}},
                         {"extensions",
                          {{"KHR_materials_ior", {{"ior", 1.0}}},
                           {"KHR_materials_clearcoat",
                            {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", roughness}}}}}};
    d.j["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_clearcoat"};
    d.j["materials"] = {coated};
    d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 4.0f, 0)}}}};
    d.node({{"mesh", 0}});
    const test::PathRender r =
        test::render_path(overhead("coat_furnace", d.text(), 1.0), int(test::sized(128, 16)));
    const test::Mean m = test::mean_all(r);
    std::printf("coat roughness %.1f: %.5f +- %.5f\n", roughness, m.mean, m.se);
    EXPECT_LE(m.mean, 1.0 + 4.0 * m.se) << "energy created";
    if (roughness == 0.0)
      EXPECT_NEAR(m.mean, 1.0, 4.0 * m.se + 1e-4);
    else
      EXPECT_GT(m.mean, 0.97);
  }
}

// clearcoatTexture's R scales the coat per texel: a black Lambertian
// (index 1: no layer of its own) under a smooth coat whose texture is 0 on
// the half x < 0 and 1 on x > 0, in a white furnace, is black exactly on
// the first half and shows the coat's Fresnel reflectance of the sky,
// about F0 = 0.04 seen from above, on the second. (The image's left is +x.)
TEST(GltfMaterials, TheCoatsTextureScalesItPerTexel) {
  Doc d;
  std::string ppm = "P6 2 1 255\n";
  ppm += {char(0), char(0), char(0), char(255), char(255), char(255)};
  d.j["images"] = {{{"bufferView", d.view(ppm)}, {"mimeType", "image/png"}}};
  d.j["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}}};
  d.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  const json coated = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}}},
                       {"extensions",
                        {{"KHR_materials_ior", {{"ior", 1.0}}},
                         {"KHR_materials_clearcoat",
                          {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.0},
                           {"clearcoatTexture", {{"index", 0}}}}}}}};
  d.j["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_clearcoat"};
  d.j["materials"] = {coated};
  d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 4.0f, 0)}}}};
  d.node({{"mesh", 0}});
  std::vector<std::string> warnings;
  LoadOptions lo;
  lo.warnings = &warnings;
  const std::string path = overhead("coat_texture", d.text(), 1.0);
  const Scene s = load_scene(path, lo);
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  EXPECT_GE(s.materials[0].clearcoat_texture, 0);
  const test::PathRender r = test::render_path(path, int(test::sized(64, 16)));
  for (int y = 0; y < 16; ++y)
    for (int x = 9; x < 16; ++x) ASSERT_EQ(r.image.at(x, y)[1], 0.0f) << "no coat, a black base: " << x << ", " << y;
  // The coat is a delta lobe picked a tenth of the time: its pixels are
  // noisy, its mean is not.
  const test::Mean coat = test::mean_over(r, [](int x, int) { return x < 7; });
  std::printf("coated half: %.5f +- %.5f\n", coat.mean, coat.se);
  EXPECT_NEAR(coat.mean, 0.04, 4.0 * coat.se + 5e-4);
  EXPECT_LT(coat.se, 0.004);
}

}  // namespace
}  // namespace caustica
