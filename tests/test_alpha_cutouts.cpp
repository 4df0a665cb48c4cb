// glTF alpha cut-outs (issue 43): alphaMode MASK and BLEND become holes in
// the traversal (kernels/lib/alpha_cutout.h), so camera rays, shadow rays
// and photons all see the same mask. Checked exactly where the answer is
// exact: under a light straight down, with one scattering event, a pixel
// seen through a hole shows the lit floor (the camera ray passed the hole,
// and so did the floor's shadow ray) and a pixel on the kept half shows
// the quad, to float precision; a BLEND quad of alpha a shows
// a L_quad + (1 - a)^2 L_floor on average (kept by the camera ray with
// probability a; else the floor, whose shadow ray passes with 1 - a); a
// fully cut-out quad leaves the photon pass's caustic as if it were not
// there, and an opaque one blocks it.
#include <gtest/gtest.h>

#include <stb/stb_image_write.h>

#include <glm/gtc/packing.hpp>

#include <cmath>

#include "host/scene/alpha_cutouts.h"
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

constexpr double kPi = 3.14159265358979323846;

// A w x 1 RGBA PNG (stb_image_write, linked from the renderer): grey
// texels with these alpha codes.
std::string png_alpha_row(const std::vector<int>& alpha) {
  std::vector<unsigned char> rgba;
  for (int a : alpha) rgba.insert(rgba.end(), {200, 200, 200, static_cast<unsigned char>(a)});
  std::string png;
  auto append = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size_t(size));
  };
  stbi_write_png_to_func(append, &png, int(alpha.size()), 1, 4, rgba.data(), int(alpha.size()) * 4);
  return png;
}

// A horizontal square of half-size `half` at height y, normal +y, glTF uv
// u = (x + half) / (2 half): its primitive with `material`.
json square(Doc& d, float y, float half, int material) {
  const std::vector<float> pos = {-half, y, -half, -half, y, half, half, y, half, half, y, -half};
  const std::vector<float> uv = {0, 0, 0, 1, 1, 1, 1, 0};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  return json{{"attributes", {{"POSITION", d.floats(pos, "VEC3", 3)}, {"TEXCOORD_0", d.floats(uv, "VEC2", 2)}}},
              {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
              {"material", material}};
}

json lambert(double grey) {
  return json{{"pbrMetallicRoughness", {{"baseColorFactor", {grey, grey, grey, 1.0}}, {"metallicFactor", 0.0}}},
              {"extensions", {{"KHR_materials_ior", {{"ior", 1.0}}}}}};  // F0 = 0: an exact Lambertian
}

// A floor (white, 3 x 3 half-size) and a grey (0.5) quad (half-size 1) at
// height 0.5 with `quad_material`'s alpha settings; a PNG for its base
// colour texture when `png` is not empty (nearest, clamped).
std::string floor_and_quad(json quad_material, const std::string& png) {
  Doc d;
  d.j["extensionsUsed"] = {"KHR_materials_ior"};
  json quad = lambert(0.5);
  for (auto& [key, value] : quad_material.items()) quad[key] = value;
  if (!png.empty()) {
    d.j["images"] = {{{"bufferView", d.view(png)}, {"mimeType", "image/png"}}};
    d.j["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
    d.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
    quad["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  }
  d.j["materials"] = {lambert(1.0), quad};
  d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 3.0f, 0), square(d, 0.5f, 1.0f, 1)}}}};
  d.node({{"mesh", 0}});
  return d.text();
}

// Seen from straight above (image right = +x), lit straight down with
// irradiance 2, one scattering event.
std::string overhead_scene(const std::string& name, const std::string& gltf) {
  test::write_scene(name + ".gltf", gltf);
  return test::write_scene(name + ".json", R"({"rendermode": "pathtracer", "nbounces": 1,
    "camera": {"width": 32, "height": 32, "position": [0, 5, 0], "lookAt": [0, 0, 0], "upVector": [0, 0, -1],
               "fov": 30},
    "scene": {"backgroundcolor": [0, 0, 0],
      "lightsources": [{"type": "directional", "direction": [0, -1, 0], "intensity": [2, 2, 2]}],
      "shapes": [{"type": "mesh", "file": ")" + name + R"(.gltf"}]}})");
}

// Where pixel (px, py)'s centre ray crosses the quad's height (x, z): the
// image's right is -x (the camera's right is up x forward), its top -z.
glm::dvec2 at_quad_height(int px, int py, int size) {
  const double half_width = 4.5 * std::tan(15.0 * kPi / 180.0);
  return {(1.0 - (px + 0.5) / size * 2.0) * half_width, ((py + 0.5) / size * 2.0 - 1.0) * half_width};
}

const double kFloorLit = 1.0 * 2.0 / kPi, kQuadLit = 0.5 * 2.0 / kPi;

TEST(AlphaCutouts, ImportMakesMaskAndBlendMaterialsAndKeepsTheImagesAlpha) {
  Scene scene;
  TextureLibrary textures(scene);
  const std::string mask = floor_and_quad({{"alphaMode", "MASK"}, {"alphaCutoff", 0.4}}, png_alpha_row({51, 230}));
  const GltfModel g = import_gltf_bytes("mask.gltf", mask, ".", textures, false);
  for (const std::string& w : g.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  const Material& m = g.materials[1];
  EXPECT_TRUE(m.flags & MATERIAL_ALPHA_MASK);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.4f);
  EXPECT_FLOAT_EQ(m.alpha_factor, 1.0f);
  EXPECT_FALSE(g.materials[0].flags & (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND));
  ASSERT_GE(m.texture, 0);
  const Texture& t = scene.textures[size_t(m.texture)];
  EXPECT_NEAR(glm::unpackHalf1x16(scene.texels[size_t(t.offset) * 4 + 3]), 51 / 255.0, 1e-3);
  EXPECT_NEAR(glm::unpackHalf1x16(scene.texels[(size_t(t.offset) + 1) * 4 + 3]), 230 / 255.0, 1e-3);

  json blend = lambert(0.5);
  blend["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.5, 0.5, 0.3};
  const GltfModel b = import_gltf_bytes("blend.gltf", floor_and_quad({{"alphaMode", "BLEND"},
      {"pbrMetallicRoughness", blend["pbrMetallicRoughness"]}}, ""), ".", textures, false);
  EXPECT_TRUE(b.materials[1].flags & MATERIAL_ALPHA_BLEND);
  EXPECT_FLOAT_EQ(b.materials[1].alpha_factor, 0.3f);

  EXPECT_TRUE(test::Contains(test::error_of([&] {
                               import_gltf_bytes("bad.gltf", floor_and_quad({{"alphaMode", "CUTOUT"}}, ""), ".",
                                                 textures, false);
                             }),
                             {"bad.gltf: /materials/1/alphaMode: expected \"OPAQUE\", \"MASK\" or \"BLEND\"",
                              "\"CUTOUT\""}));
}

TEST(AlphaCutouts, TheTraversalsRecordsCarryTheTexturesCornersAndOnlyCutOutTrianglesAreMarked) {
  const Scene s = load_scene(overhead_scene(
      "alpha_records", floor_and_quad({{"alphaMode", "MASK"}, {"alphaCutoff", 0.5}}, png_alpha_row({51, 230}))));
  EXPECT_TRUE(analyse_scene(s, RenderMode::Path).alpha_cutouts);
  EXPECT_TRUE(analyse_scene(s, RenderMode::Binary).alpha_cutouts) << "binary's rays see holes too";
  const std::vector<TriangleAlpha> a = triangle_alpha(s);
  ASSERT_EQ(a.size(), 4u);
  int masked = 0;
  for (const TriangleAlpha& t : a) {
    if (t.mode == ALPHA_OPAQUE) continue;
    ++masked;
    EXPECT_EQ(t.mode, ALPHA_MASK);
    EXPECT_EQ(t.width, 2u);
    EXPECT_EQ(t.sampling, TEXTURE_NEAREST | TEXTURE_CLAMP_U | TEXTURE_CLAMP_V);
  }
  EXPECT_EQ(masked, 2);
  const Scene plain = load_scene(overhead_scene("alpha_plain", floor_and_quad(json::object(), "")));
  EXPECT_FALSE(analyse_scene(plain, RenderMode::Path).alpha_cutouts);
}

// The quad's left half (alpha 0.2, under the cut-off 0.5) is a hole: the
// camera sees the floor through it, lit, because the floor's shadow ray
// passes the same hole; the right half (0.9) is kept: the quad itself.
TEST(AlphaCutouts, AMaskedQuadShowsTheLitFloorThroughItsHolesAndItselfElsewhere) {
  const int size = 32;
  const std::string path = overhead_scene(
      "alpha_mask", floor_and_quad({{"alphaMode", "MASK"}, {"alphaCutoff", 0.5}}, png_alpha_row({51, 230})));
  // The quad's colour is its factor x its texel (grey 200, sRGB-decoded).
  const double textured_quad = kQuadLit * srgb_byte_to_linear(200);
  for (RenderMode mode : {RenderMode::Path, RenderMode::Binary}) {
    test::CameraRenderOptions o;
    o.spp = 4;
    const test::CameraRender r = test::render_with_camera(path, mode, o);
    int holes = 0, kept = 0;
    for (int py = 0; py < size; ++py)
      for (int px = 0; px < size; ++px) {
        const glm::dvec2 q = at_quad_height(px, py, size);
        if (std::fabs(q.y) > 0.9 || std::fabs(q.x) > 0.9 || std::fabs(q.x) < 0.15) continue;
        const float v = r.image.at(px, py)[0];
        if (mode == RenderMode::Binary) {
          EXPECT_GT(v, 0.0f) << "binary sees a surface at " << px << ", " << py;  // the floor or the quad
          continue;
        }
        if (q.x < 0.0) {
          EXPECT_NEAR(v, kFloorLit, 1e-4 * kFloorLit) << "the hole at " << px << ", " << py;
          ++holes;
        } else {
          EXPECT_NEAR(v, textured_quad, 1e-3 * textured_quad) << "the kept half at " << px << ", " << py;
          ++kept;
        }
      }
    if (mode == RenderMode::Path) {
      EXPECT_GT(holes, 100);
      EXPECT_GT(kept, 100);
    }
  }
}

// BLEND with alpha 0.3 and no texture: kept by a camera ray 30% of the
// time; the floor behind it is lit through it 70% of the time.
TEST(AlphaCutouts, ABlendedQuadIsKeptWithProbabilityAlphaByEveryRay) {
  const int size = 32;
  json material = {{"alphaMode", "BLEND"},
                   {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 0.3}}, {"metallicFactor", 0.0}}}};
  const test::PathRender r =
      test::render_path(overhead_scene("alpha_blend", floor_and_quad(material, "")), int(test::sized(64, 16)));
  const test::Mean m = test::mean_over(r, [&](int px, int py) {
    const glm::dvec2 q = at_quad_height(px, py, size);
    return std::fabs(q.x) < 0.9 && std::fabs(q.y) < 0.9;
  });
  const double want = 0.3 * kQuadLit + 0.7 * 0.7 * kFloorLit;
  std::printf("blend: %.5f +- %.5f, expected %.5f\n", m.mean, m.se, want);
  EXPECT_NEAR(m.mean, want, 4.0 * m.se);
  EXPECT_LT(m.se, 0.01 * want);
}

// The photon pass traces the same holes: a glass ball under a light
// straight down focuses a caustic on the floor; a quad above it, cut out
// everywhere (MASK, alpha 0), leaves the caustic as it is without the
// quad, within noise; kept everywhere (alpha 1) it blocks it.
TEST(AlphaCutouts, PhotonsPassTheSameHoles) {
  auto scene = [&](const std::string& name, double quad_alpha) {
    std::string shapes;
    if (quad_alpha >= 0.0) {
      Doc d;
      json m = lambert(0.5);
      m["alphaMode"] = "MASK";
      m["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.5, 0.5, quad_alpha};
      d.j["extensionsUsed"] = {"KHR_materials_ior"};
      d.j["materials"] = {m};
      d.j["meshes"] = {{{"primitives", {square(d, 1.2f, 1.0f, 0)}}}};
      d.node({{"mesh", 0}});
      test::write_scene(name + ".gltf", d.text());
      shapes = R"(, {"type": "mesh", "file": ")" + name + R"(.gltf"})";
    }
    return test::write_scene(name + ".json", R"({"nbounces": 6, "rendermode": "pathtracer",
      "camera": {"width": 32, "height": 32, "position": [0, 0.9, 0.9], "lookAt": [0, 0, 0], "upVector": [0, 1, 0],
                 "fov": 40},
      "scene": {"backgroundcolor": [0, 0, 0],
        "lightsources": [{"type": "directional", "direction": [0, -1, 0], "intensity": [2, 2, 2]}],
        "shapes": [
          {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.3,
           "material": {"isrefractive": true, "refractiveindex": 1.5, "kd": 0, "ks": 0}},
          {"type": "triangle", "v0": [-3, 0, -3], "v1": [-3, 0, 3], "v2": [3, 0, 3],
           "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
          {"type": "triangle", "v0": [-3, 0, -3], "v1": [3, 0, 3], "v2": [3, 0, -3],
           "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}})" + shapes + "]}}");
  };
  // The caustic alone: the photon pass's image less the image without it
  // (path tracing alone cannot find a delta light through smooth glass).
  auto caustic = [&](const std::string& path) {
    test::CameraRenderOptions on, off;
    on.spp = off.spp = int(test::sized(16, 2));
    on.size = off.size = int(test::sized(32, 8));  // Oclgrind: 8 x 8 pixels (about 190 s there)
    on.caustics = CausticsMode::On;
    off.caustics = CausticsMode::Off;
    const test::CameraRender with = test::render_with_camera(path, RenderMode::Path, on);
    const test::CameraRender without = test::render_with_camera(path, RenderMode::Path, off);
    double sum = 0.0;
    for (int py = 0; py < with.image.height; ++py)
      for (int px = 0; px < with.image.width; ++px) sum += with.image.at(px, py)[0] - without.image.at(px, py)[0];
    return sum;
  };
  const double bare = caustic(scene("alpha_photons_bare", -1.0));
  const double cut = caustic(scene("alpha_photons_cut", 0.0));
  const double kept = caustic(scene("alpha_photons_kept", 1.0));
  std::printf("caustic sums: no quad %.3f, cut-out quad %.3f, opaque quad %.3f\n", bare, cut, kept);
  EXPECT_GT(bare, test::on_simulator() ? 0.1 : 1.0) << "the scene has a caustic";
  EXPECT_NEAR(cut, bare, 0.05 * bare) << "photons pass a quad cut out everywhere";
  EXPECT_LT(std::fabs(kept), 0.02 * bare) << "photons stop at an opaque quad";
}

// A cut-out emitter lights only from where it is there: a ceiling quad
// facing down, emissive, masked away on one half, over a white floor.
// Light sampling draws points on the whole quad (its density is by area)
// and must count none from the holes; BSDF sampling finds the emitter only
// where it is there. The two strategies, and MIS, give one image.
TEST(AlphaCutouts, ACutOutEmitterLightsOnlyFromWhereItIsThere) {
  Doc d;
  d.j["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_emissive_strength"};
  json lamp = {{"alphaMode", "MASK"},
               {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
               {"emissiveFactor", {1, 1, 1}},
               {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}};
  d.j["images"] = {{{"bufferView", d.view(png_alpha_row({255, 0}))}, {"mimeType", "image/png"}}};
  d.j["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
  d.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  lamp["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  d.j["materials"] = {lambert(1.0), lamp};
  // The lamp at height 1 facing down (its winding reversed).
  json ceiling = square(d, 1.0f, 0.5f, 1);
  const std::vector<uint16_t> down = {0, 2, 1, 0, 3, 2};
  ceiling["indices"] = d.accessor(d.view(Doc::bytes(down)), 5123, down.size(), "SCALAR");
  d.j["meshes"] = {{{"primitives", {square(d, 0.0f, 3.0f, 0), ceiling}}}};
  d.node({{"mesh", 0}});
  test::write_scene("alpha_lamp.gltf", d.text());
  const std::string path = test::write_scene("alpha_lamp.json", R"({"rendermode": "pathtracer", "nbounces": 1,
    "camera": {"width": 16, "height": 16, "position": [0, 0.8, 2.5], "lookAt": [0, 0, 0], "upVector": [0, 1, 0],
               "fov": 40},
    "scene": {"backgroundcolor": [0, 0, 0], "lightsources": [],
      "shapes": [{"type": "mesh", "file": "alpha_lamp.gltf"}]}})");
  const int spp = int(test::sized(256, 16));
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;
  test::Mean m[3];
  const uint32_t strategies[3] = {PATH_STRATEGY_NEE, PATH_STRATEGY_BSDF, PATH_STRATEGY_MIS};
  for (int i = 0; i < 3; ++i) {
    o.strategy = strategies[i];
    o.seed = uint32_t(11 * i);
    m[i] = test::mean_all(test::render_path(path, spp, o));
  }
  std::printf("light sampling %.5f +- %.5f, BSDF sampling %.5f +- %.5f, MIS %.5f +- %.5f\n", m[0].mean, m[0].se,
              m[1].mean, m[1].se, m[2].mean, m[2].se);
  EXPECT_NEAR(m[0].mean, m[1].mean, 4.0 * std::hypot(m[0].se, m[1].se)) << "light sampling counts the holes";
  EXPECT_NEAR(m[2].mean, m[1].mean, 4.0 * std::hypot(m[2].se, m[1].se));
  EXPECT_GT(m[0].mean, 20.0 * m[0].se) << "the lamp lights the floor";
}

}  // namespace
}  // namespace caustica
