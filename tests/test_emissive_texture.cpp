// glTF's emissiveTexture per texel (issue 24): the radiance of an emissive
// surface at a point is emissiveFactor x the texture's texel there
// (sRGB-decoded and filtered like base colour) wherever that emission is
// used: seen by camera and BSDF-sampled rays (lib/material.h), at the point
// next-event estimation samples on a triangle light and at a photon's start
// (lib/lights/triangle_light.h through lights.h's light_emission_texel).
// Checked against what the texture says, not against the code:
// - the import: the factor and the texture, no warning; the light table's
//   triangle lights name their triangle and texture and are picked by the
//   texture's mean; an unreadable image and a texture coordinate set other
//   than 0 are named in warnings by their JSON pointers;
// - a camera-facing quad: pixels whose whole footprint reads one quadrant
//   of a 4 x 4 texture of four colours see factor x that texel, in path
//   mode and in phong;
// - a floor lit only by a quad whose texture is bright red on one half and
//   dark on the other: light sampling alone, BSDF sampling alone and MIS
//   agree within their errors (a wrong texel or density at the sampled
//   point would set them apart), and the floor's two sides differ (the
//   texture's mean, the former approximation, lights both alike);
// - the photons that quad emits carry the integral of factor x texel over
//   each half of it.
#include <gtest/gtest.h>

#include <glm/gtc/packing.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "host/lights/light_table.h"
#include "host/scene/load_scene.h"
#include "host/scene/textures.h"
#include "kernels/shared/camera.h"
#include "tests/support/gltf_doc.h"
#include "tests/support/path_render.h"
#include "tests/support/photon_emission.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;
using test::Doc;

constexpr double kPi = 3.14159265358979323846;

// emissiveFactor (1, 0.5, 0.25) x emissiveStrength 4.
const glm::dvec3 kFactor(4.0, 2.0, 1.0);

struct Rgb8 {
  int r, g, b;
};

// A binary PPM of w x h texels, row 0 the top; texel(x, y) gives each.
template <class Texel>
std::string ppm(int w, int h, Texel texel) {
  std::string s = "P6 " + std::to_string(w) + " " + std::to_string(h) + " 255\n";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Rgb8 c = texel(x, y);
      s += char(c.r), s += char(c.g), s += char(c.b);
    }
  return s;
}

// What the kernels read for an 8-bit code: sRGB-decoded, stored as a half.
double stored(int code) { return glm::unpackHalf1x16(glm::packHalf1x16(srgb_byte_to_linear(uint8_t(code)))); }
glm::dvec3 stored(Rgb8 c) { return glm::dvec3(stored(c.r), stored(c.g), stored(c.b)); }

// A quad (two triangles, corners in order, counter-clockwise seen from its
// emitting side) with glTF texture coordinates at the corners, emitting
// kFactor x the image `texture`; base colour black (it reflects almost
// nothing). `extra` primitives may follow in the same mesh.
struct Quad {
  std::vector<float> corners;  // 4 x 3
  std::vector<float> uv;       // 4 x 2, glTF's: (0, 0) the image's top-left
};
std::string emitter_file(const Quad& q, const std::string& texture, bool double_sided, bool with_floor) {
  Doc d;
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  auto prim = [&](const std::vector<float>& pos, const std::vector<float>* uv, int material) {
    json attributes = {{"POSITION", d.floats(pos, "VEC3", 3)}};
    if (uv) attributes["TEXCOORD_0"] = d.floats(*uv, "VEC2", 2);
    return json{{"attributes", attributes},
                {"indices", d.accessor(d.view(Doc::bytes(idx)), 5123, idx.size(), "SCALAR")},
                {"material", material}};
  };
  d.j["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  d.j["images"] = {{{"bufferView", d.view(texture)}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  d.j["materials"] = {
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}}},
       {"emissiveFactor", {1.0, 0.5, 0.25}},
       {"emissiveTexture", {{"index", 0}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}},
       {"doubleSided", double_sided}},
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0.0}}}}};
  json prims = {prim(q.corners, &q.uv, 0)};
  // A 6 x 6 floor in y = 0, facing up.
  if (with_floor) prims.push_back(prim({-3, 0, -3, -3, 0, 3, 3, 0, 3, 3, 0, -3}, nullptr, 1));
  d.j["meshes"] = {{{"primitives", prims}}};
  d.node({{"mesh", 0}});
  return d.text();
}

std::string scene_file(const std::string& name, const std::string& gltf, const std::string& camera, int nbounces) {
  test::write_scene(name + ".gltf", gltf);
  return test::write_scene(name + ".json", R"({"rendermode": "pathtracer", "nbounces": )" + std::to_string(nbounces) +
                                               R"(, "camera": )" + camera + R"(,
    "scene": {"backgroundcolor": [0, 0, 0], "shapes": [{"type": "mesh", "file": ")" +
                                               name + R"(.gltf"}]}})");
}

// --- a camera-facing quad, 4 x 4 texels in four 2 x 2 quadrants --------

const Rgb8 kQuadrants[2][2] = {{{255, 64, 0}, {0, 255, 128}},   // top: left, right
                               {{32, 0, 255}, {200, 180, 90}}};  // bottom
Rgb8 quadrant_texel(int x, int y) { return kQuadrants[y / 2][x / 2]; }

// The square [-1, 1]^2 in z = 0; the image's top-left at (-1, 1).
const Quad kFacing = {{-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, {0, 1, 1, 1, 1, 0, 0, 0}};
const char* kFacingCamera = R"({"width": 32, "height": 32, "position": [0, 0, 3], "lookAt": [0, 0, 0],
  "upVector": [0, 1, 0], "fov": 45})";

std::string facing_scene(const std::string& name) {
  return scene_file(name, emitter_file(kFacing, ppm(4, 4, quadrant_texel), /*double_sided=*/true, false),
                    kFacingCamera, 2);
}

// Where the camera's ray through image point (px, py) meets z = 0, as
// glTF's texture coordinates of the quad there.
glm::dvec2 gltf_uv_at(const CameraGPU& camera, float px, float py) {
  float d[3];
  camera_plane_point(&camera, px, py, d);
  const double t = -camera.position.z / d[2];
  const double x = camera.position.x + t * d[0], y = camera.position.y + t * d[1];
  return glm::dvec2((x + 1.0) / 2.0, (1.0 - y) / 2.0);
}

// The quadrant (row, column) whose 2 x 2 texels alone the bilinear filter
// reads at glTF uv: within a quarter of a quadrant of its centre
// (lib/texture.h: texel centres at (i + 0.5) / 4); -1 elsewhere.
int pure_quadrant(glm::dvec2 uv) {
  auto axis = [](double t) {
    if (!(t > 0.0 && t < 1.0)) return -1;
    const double f = 2.0 * t - std::floor(2.0 * t);
    return f > 0.25 && f < 0.75 ? int(2.0 * t) : -1;
  };
  const int col = axis(uv.x), row = axis(uv.y);
  return col < 0 || row < 0 ? -1 : row * 2 + col;
}

// Every pixel whose four corners read the same pure quadrant sees
// kFactor x its texel; at least 4 such pixels in each quadrant.
void expect_factor_times_texel(const test::CameraRender& r, const char* mode) {
  int checked[4] = {0, 0, 0, 0};
  for (int y = 0; y < r.image.height; ++y)
    for (int x = 0; x < r.image.width; ++x) {
      const int q = pure_quadrant(gltf_uv_at(r.camera, float(x), float(y)));
      if (q < 0 || pure_quadrant(gltf_uv_at(r.camera, x + 1.0f, float(y))) != q ||
          pure_quadrant(gltf_uv_at(r.camera, float(x), y + 1.0f)) != q ||
          pure_quadrant(gltf_uv_at(r.camera, x + 1.0f, y + 1.0f)) != q)
        continue;
      ++checked[q];
      const glm::dvec3 expected = kFactor * stored(kQuadrants[q / 2][q % 2]);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.image.at(x, y)[c], expected[c], 1e-4 * expected[c] + 1e-6)
            << mode << ": pixel (" << x << ", " << y << ") quadrant " << q << " channel " << c;
    }
  for (int q = 0; q < 4; ++q) EXPECT_GE(checked[q], 4) << mode << ": quadrant " << q << " barely seen";
}

TEST(EmissiveTexture, ImportKeepsTheFactorAndTheTextureWithoutAWarning) {
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(facing_scene("import"), o);
  for (const std::string& w : warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(s.triangles.size(), 2u);
  const Material& m = s.materials[s.triangles[0].material];
  EXPECT_FLOAT_EQ(m.emission.x, float(kFactor.x));
  EXPECT_FLOAT_EQ(m.emission.y, float(kFactor.y));
  EXPECT_FLOAT_EQ(m.emission.z, float(kFactor.z));
  ASSERT_GE(m.emission_texture, 0);
  const Texture& tex = s.textures[size_t(m.emission_texture)];
  ASSERT_EQ(tex.kind, TEXTURE_IMAGE);
  ASSERT_EQ(tex.width * tex.height, 16u);
  // sRGB-decoded, row 0 the image's top.
  EXPECT_NEAR(glm::unpackHalf1x16(s.texels[size_t(tex.offset) * 4 + 1]), stored(64), 1e-6);
  EXPECT_NEAR(glm::unpackHalf1x16(s.texels[(size_t(tex.offset) + 15) * 4 + 2]), stored(90), 1e-6);

  // The light table: each triangle a light naming itself and the texture,
  // picked by factor x the texture's mean (equal areas: one half each).
  const LightTable table = build_light_table(s);
  ASSERT_EQ(table.lights.size(), 2u);
  for (uint32_t i = 0; i < 2; ++i) {
    const Light& l = table.lights[table.light_of_triangle[i]];
    EXPECT_EQ(l.kind, uint32_t(LIGHT_TRIANGLE));
    EXPECT_TRUE(l.flags & LIGHT_EMISSION_TEXTURE);
    EXPECT_TRUE(l.flags & LIGHT_TWO_SIDED);
    EXPECT_EQ(as_uint(l.p0.w), i);
    EXPECT_EQ(as_uint(l.p1.w), uint32_t(m.emission_texture));
    EXPECT_NEAR(l.select_probability, 0.5f, 1e-6f);
  }
}

// What is still not read is named by its JSON pointer: a texture
// coordinate set other than 0 (TEXCOORD_0 is used); an unreadable image
// emits the visible magenta/black checker, with a warning.
TEST(EmissiveTexture, UnreadableImagesAndOtherCoordinateSetsAreNamed) {
  json file = json::parse(emitter_file(kFacing, "not an image", /*double_sided=*/true, false));
  file["materials"][0]["emissiveTexture"]["texCoord"] = 1;
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warnings = &warnings;
  const Scene s = load_scene(scene_file("unreadable", file.dump(), kFacingCamera, 2), o);
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  // The material's only texture names TEXCOORD_1, which the primitive lacks.
  EXPECT_TRUE(test::Contains(all, {"/meshes/0/primitives/0/attributes",
                                   "the material's textures read TEXCOORD_1, which the primitive lacks; "
                                   "TEXCOORD_0 is used"}))
      << all;
  EXPECT_TRUE(test::Contains(all, {"/materials/0/emissiveTexture: warning: texture /textures/0 cannot be read",
                                   "magenta/black checker"}))
      << all;
  const Material& m = s.materials[s.triangles[0].material];
  ASSERT_GE(m.emission_texture, 0);
  EXPECT_EQ(s.textures[size_t(m.emission_texture)].kind, TEXTURE_CHECKER);
}

TEST(EmissiveTexture, PathModeSeesFactorTimesTexel) {
  test::CameraRenderOptions o;
  o.spp = 4;
  expect_factor_times_texel(test::render_with_camera(facing_scene("facing_path"), RenderMode::Path, o), "path");
}

TEST(EmissiveTexture, PhongSeesFactorTimesTexel) {
  expect_factor_times_texel(test::render_with_camera(facing_scene("facing_phong"), RenderMode::Phong), "phong");
}

// --- a floor under a quad, bright red on one half and dark on the other --

// 8 x 1 texels: four bright red (A), four dark grey (B).
const Rgb8 kBright = {255, 40, 20}, kDark = {12, 12, 12};
Rgb8 halves_texel(int x, int) { return x < 4 ? kBright : kDark; }

// 2 x 1 at height 1.2 facing down (one-sided); u runs along x, so x < 0 is
// the bright half.
constexpr float kHeight = 1.2f;
const Quad kCeiling = {{-1, kHeight, -0.5f, 1, kHeight, -0.5f, 1, kHeight, 0.5f, -1, kHeight, 0.5f},
                       {0, 0, 1, 0, 1, 1, 0, 1}};

std::string ceiling_scene(const std::string& name) {
  // Below the quad, looking at the floor: the light is out of view.
  return scene_file(name, emitter_file(kCeiling, ppm(8, 1, halves_texel), /*double_sided=*/false, true),
                    R"({"width": 32, "height": 16, "position": [0, 0.8, 2.6], "lookAt": [0, 0, 0],
                        "upVector": [0, 1, 0], "fov": 40})",
                    1);
}

TEST(EmissiveTexture, LightSamplingAgreesWithBsdfSamplingAndSeesEachTexel) {
  const std::string scene = ceiling_scene("ceiling");
  const int spp = int(test::sized(64, 8));
  test::PathRenderOptions o;
  o.caustics = CausticsMode::Off;
  o.strategy = PATH_STRATEGY_NEE;
  const test::PathRender nee = test::render_path(scene, spp, o);
  o.strategy = PATH_STRATEGY_BSDF;
  o.seed = 3;
  const test::PathRender bsdf = test::render_path(scene, 4 * spp, o);
  o.strategy = PATH_STRATEGY_MIS;
  o.seed = 5;
  const test::PathRender mis = test::render_path(scene, spp, o);
  const int w = nee.image.width;
  // The floor's two sides, clear of the middle column.
  auto left = [&](int x, int) { return x < w / 2 - 2; };
  auto right = [&](int x, int) { return x >= w / 2 + 2; };
  struct Side {
    const char* name;
    test::Mean nee, bsdf, mis;
  };
  const Side sides[2] = {
      {"left", test::mean_over(nee, left), test::mean_over(bsdf, left), test::mean_over(mis, left)},
      {"right", test::mean_over(nee, right), test::mean_over(bsdf, right), test::mean_over(mis, right)}};
  for (const Side& s : sides) {
    std::printf("%-5s nee %.5f +- %.5f  bsdf %.5f +- %.5f  mis %.5f +- %.5f\n", s.name, s.nee.mean, s.nee.se,
                s.bsdf.mean, s.bsdf.se, s.mis.mean, s.mis.se);
    EXPECT_NEAR(s.nee.mean, s.bsdf.mean, 4.0 * std::hypot(s.nee.se, s.bsdf.se)) << s.name;
    EXPECT_NEAR(s.mis.mean, s.bsdf.mean, 4.0 * std::hypot(s.mis.se, s.bsdf.se)) << s.name;
    EXPECT_NEAR(s.mis.mean, s.nee.mean, 4.0 * std::hypot(s.mis.se, s.nee.se)) << s.name;
  }
  // The scene is symmetric in x but for the texture: under its mean colour
  // the two sides would be alike.
  const test::Mean& l = sides[0].mis;
  const test::Mean& r = sides[1].mis;
  EXPECT_GT(std::fabs(l.mean - r.mean), 10.0 * std::hypot(l.se, r.se)) << "the two halves of the texture light alike";
  EXPECT_GT(std::max(l.mean, r.mean), 1.5 * std::min(l.mean, r.mean));
}

// Photons leave each half of the quad with its share of the power: pi x
// area x kFactor x the mean of the filtered texture over that half. With
// the bilinear filter and wrapping of lib/texture.h, over u in [0, 1/2]
// texels 0 and 3 count 7/8 each, texels 1 and 2 whole, and texels 7 and
// 4 (bright's neighbours across the wrap and the seam) 1/8 each: a mean of
// (15 A + B) / 16, and (15 B + A) / 16 over the other half.
TEST(EmissiveTexture, PhotonsCarryTheTexelsIntegralOverEachHalf) {
  SessionOptions so;
  so.scene_path = ceiling_scene("ceiling_photons");
  so.device = test::device_spec();
  so.mode = RenderMode::Path;
  so.caustics = CausticsMode::On;
  so.width = so.height = 8;
  auto s = prepare_session(so);
  const LightTable table = build_light_table(s->scene);
  ASSERT_EQ(table.lights.size(), 2u);
  const uint32_t n = uint32_t(test::sized(1u << 18, 1u << 11));
  const std::vector<cs_float4> flux = test::emit_photons_on_device(*s, table, n, "power"),
                               origin = test::emit_photons_on_device(*s, table, n, "origin");
  const glm::dvec3 a = stored(kBright), b = stored(kDark);
  const glm::dvec3 expected[2] = {kPi * 1.0 * kFactor * (15.0 * a + b) / 16.0,   // x < 0: bright
                                  kPi * 1.0 * kFactor * (15.0 * b + a) / 16.0};  // x > 0: dark
  glm::dvec3 sum[2] = {glm::dvec3(0.0), glm::dvec3(0.0)}, sum2[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  for (uint32_t i = 0; i < n; ++i) {
    const int half = origin[i].x < 0.0f ? 0 : 1;
    const glm::dvec3 f(flux[i].x, flux[i].y, flux[i].z);
    // Every photon counts in both sums: zero in the half it did not leave.
    sum[half] += f, sum2[half] += f * f;
  }
  for (int h = 0; h < 2; ++h)
    for (int c = 0; c < 3; ++c) {
      const double se = std::sqrt(std::max(0.0, sum2[h][c] - sum[h][c] * sum[h][c] / n));  // of the sum
      std::printf("half %d channel %d: flux %.5f (se %.5f), expected %.5f\n", h, c, sum[h][c], se, expected[h][c]);
      EXPECT_NEAR(sum[h][c], expected[h][c], 5.0 * se + 1e-6 * expected[h][c]) << "half " << h << " channel " << c;
    }
  // The texture's mean (the former approximation) would give both halves
  // (A + B) / 2: the bright half carries several times the dark one's.
  EXPECT_GT(sum[0].x, 4.0 * sum[1].x);
}

}  // namespace
}  // namespace caustica
