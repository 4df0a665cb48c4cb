// glTF 2.0 import against the files in ../shared/models/gltf (skipped when
// absent; read where they lie, never copied): every valid file of the Open
// Asset Import Library's test set loads and renders (binary mode, tiny
// image), every broken one fails with one caustica::Error naming the file and
// the JSON pointer of what is wrong, and the Cornell box assimp converted to
// glTF, placed by a coursework scene as a mesh, renders like the OBJ it was
// converted from (means per channel and per image quarter within noise).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <glm/glm.hpp>

#include "host/app/session.h"
#include "host/error.h"
#include "host/scene/load_scene.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

namespace fs = std::filesystem;

// Broken files (relative to assimp-tests/) and what their one error must
// name besides the file: the pointer of the fault.
const std::vector<std::pair<std::string, std::string>> kBroken = {
    {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "/accessors/2: element 0 is not finite"},
    {"IndexOutOfRange/IndexOutOfRange.gltf", "/accessors/0: element 0 is index 255, out of range"},
    {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "/accessors/0: element 0 is index 65535, out of range"},
    {"MissingBin/BoxTextured.gltf", "/buffers/0/uri: expected an existing file"},
    {"RecursiveNodes/RecursiveNodes.gltf", "/nodes/1/children/0: node 0 is its own ancestor"},
    {"SchemaFailures/sceneWrongType.gltf", "/scene: expected an index"},
    {"draco/2CylinderEngine.gltf", "/extensionsRequired/0: required extension KHR_draco_mesh_compression"},
    {"wrongTypes/badArray.gltf", "/meshes/0/primitives: expected an array"},
    {"wrongTypes/badExtension.gltf", "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/"
                                     "KHR_texture_transform: expected an extension object"},
    {"wrongTypes/badNumber.gltf", "/materials/0/normalTexture/scale: expected a number"},
    {"wrongTypes/badObject.gltf", "/materials/0/pbrMetallicRoughness: expected an object"},
    {"wrongTypes/badString.gltf", "/scenes/0/name: expected a string"},
    {"wrongTypes/badUint.gltf", "/materials/0/pbrMetallicRoughness/baseColorTexture/index: expected an index"},
};

std::vector<fs::path> gltf_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".gltf" || ext == ".glb") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(GltfFiles, EveryValidAssimpFileRendersAndEveryBrokenOneFailsPrecisely) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const fs::path dir = fs::path(shared) / "models" / "gltf" / "assimp-tests";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " absent";
  const std::vector<fs::path> files = gltf_files(dir);
  ASSERT_GE(files.size(), 40u);
  int rendered = 0, failed = 0;
  for (const fs::path& f : files) {
    const std::string relative = f.lexically_relative(dir).string();
    auto broken = std::find_if(kBroken.begin(), kBroken.end(), [&](const auto& b) { return b.first == relative; });
    SessionOptions o;
    o.scene_path = f.string();
    o.mode = RenderMode::Binary;
    o.width = 24;
    o.height = 16;
    o.device = test::device_spec();
    if (broken != kBroken.end()) {
      const std::string message = test::error_of([&] { prepare_session(o); });
      EXPECT_TRUE(test::Contains(message, {f.string() + ": ", broken->second})) << relative;
      ++failed;
      continue;
    }
    std::unique_ptr<Session> session;
    try {
      session = prepare_session(o);
    } catch (const Error& e) {
      ADD_FAILURE() << relative << " is valid but failed: " << e.what();
      continue;
    }
    RenderStats stats;
    const ImageF image = session->renderer->render(&stats);
    EXPECT_EQ(stats.film.changed(), 0u) << relative;
    EXPECT_EQ(image.width, 24);
    ++rendered;
  }
  EXPECT_EQ(failed, static_cast<int>(kBroken.size()));
  EXPECT_EQ(rendered + failed, static_cast<int>(files.size()));
}

// The extension's own test model (assimp-tests/textureTransform, Khronos'
// TextureTransformTest, CC0): its top row shows a check mark only where the
// offset is applied (a yellow "not supported" sign otherwise), and in its
// bottom row each arrow must point at the green marker (the red one means
// the rotation turned the wrong way). Probed at the arrows' tips and the
// top row's centres, as fractions of the image (the default camera frames
// the model the same way at any size): docs/gltf.md shows the image.
TEST(GltfFiles, TextureTransformTestShowsEveryMarkerGreen) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const fs::path file =
      fs::path(shared) / "models" / "gltf" / "assimp-tests" / "textureTransform" / "TextureTransformTest.gltf";
  if (!fs::exists(file)) GTEST_SKIP() << file << " absent";
  // 120,000 paths are minutes on Oclgrind; the lookups this reaches are
  // checked there by Textures.WrapModesNearestFilterAndUvTransform.
  if (test::on_simulator()) GTEST_SKIP() << "too many paths for the simulator";
  test::PathRenderOptions o;
  o.width = 400;
  o.height = 300;
  const test::PathRender r = test::render_path(file.string(), 4, o);
  auto at = [&](float fx, float fy) {
    const float* c = r.image.at(int(fx * o.width), int(fy * o.height));
    return glm::vec3(c[0], c[1], c[2]);
  };
  // The top row: green, blue and cyan squares, none yellow (red + green).
  const glm::vec3 u = at(0.231f, 0.267f), v = at(0.425f, 0.267f), uv = at(0.621f, 0.267f);
  EXPECT_TRUE(u.y > 4.0f * u.x && u.y > 4.0f * u.z) << "offset in u: " << u.x << " " << u.y << " " << u.z;
  EXPECT_TRUE(v.z > 4.0f * v.x && v.z > 4.0f * v.y) << "offset in v: " << v.x << " " << v.y << " " << v.z;
  EXPECT_TRUE(uv.y > 4.0f * uv.x && uv.z > 4.0f * uv.x) << "offset in uv: " << uv.x << " " << uv.y << " " << uv.z;
  // On the rotated arrows near their tips: black (the light background
  // where an arrow turned the other way, or not at all); past the scaled
  // arrow's tip: the background (the unscaled arrow reaches there).
  auto brightness = [&](float fx, float fy) {
    const glm::vec3 c = at(fx, fy);
    return (c.x + c.y + c.z) / 3.0f;
  };
  EXPECT_LT(brightness(0.269f, 0.683f), 0.2f) << "rotation";
  EXPECT_LT(brightness(0.674f, 0.640f), 0.2f) << "offset, rotation and scale";
  EXPECT_GT(brightness(0.519f, 0.642f), 0.5f) << "scale";
}

// Points and lines are skipped with a warning naming the mode: a file of
// nothing else renders its background and says so.
TEST(GltfFiles, UnsupportedPrimitiveModesAreNamedInWarnings) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const fs::path dir = fs::path(shared) / "models" / "gltf" / "assimp-tests" / "glTF-Asset-Generator" /
                       "Mesh_PrimitiveMode";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " absent";
  std::vector<std::string> warnings;
  LoadOptions options;
  options.warnings = &warnings;
  load_scene((dir / "Mesh_PrimitiveMode_01.gltf").string(), options);
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(test::Contains(all, {"/meshes/0/primitives/0/mode: warning: primitive mode LINES (1) is not supported",
                                   "places no triangles"}));
  // Strips and fans are triangles: Mesh_PrimitiveMode_05/06 (strip, fan) load two each.
  for (const char* name : {"Mesh_PrimitiveMode_05.gltf", "Mesh_PrimitiveMode_06.gltf"}) {
    warnings.clear();
    const Scene s = load_scene((dir / name).string(), options);
    EXPECT_EQ(s.triangles.size(), 2u) << name;
  }
}

std::string cornell_scene(const std::string& mesh) {
  return R"({"nbounces": 6, "rendermode": "pathtracer",
  "camera": {"width": 40, "height": 40, "position": [0, 1, 3.6], "lookAt": [0, 1, 0], "upVector": [0, 1, 0], "fov": 38},
  "scene": {"backgroundcolor": [0, 0, 0], "lightsources": [],
            "shapes": [{"type": "mesh", "file": ")" + mesh + R"("}]}})";
}

// The converted box's light has emissiveFactor (17, 12, 4), beyond glTF's
// [0, 1]; honoured, it lights the room as the OBJ's Ke does. Both halves of
// each render are independent, so each mean has a standard error
// (path_render.h); the two renders, with different seeds, must agree within
// 4 of them, over the whole image and each quarter.
TEST(GltfFiles, ConvertedCornellBoxRendersLikeTheObjItCameFrom) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const fs::path gltf = fs::path(shared) / "models" / "gltf" / "converted" / "cornell-box" / "cornell_box.gltf";
  const fs::path obj = fs::path(shared) / "models" / "cornell-box" / "CornellBox-Original.obj";
  if (!fs::exists(gltf) || !fs::exists(obj)) GTEST_SKIP() << "Cornell box files absent";
  const int spp = static_cast<int>(test::sized(64, 8));
  // Different seeds: the two renders' noise is independent (the same seed
  // would give the same image for the same geometry and materials).
  test::PathRenderOptions other_seed;
  other_seed.seed = 7;
  const test::PathRender a =
      test::render_path(test::write_scene("gltf.json", cornell_scene(gltf.string())), spp, other_seed);
  const test::PathRender b = test::render_path(test::write_scene("obj.json", cornell_scene(obj.string())), spp);
  ASSERT_EQ(a.image.width, b.image.width);
  for (int q = -1; q < 4; ++q) {
    auto keep = [&](int x, int y) { return q < 0 || (x * 2 / a.image.width + 2 * (y * 2 / a.image.height)) == q; };
    const test::Mean ma = test::mean_over(a, keep), mb = test::mean_over(b, keep);
    const double se = std::sqrt(ma.se * ma.se + mb.se * mb.se);
    if (q < 0) std::printf("[cornell] glTF %.5f +- %.5f, OBJ %.5f +- %.5f\n", ma.mean, ma.se, mb.mean, mb.se);
    EXPECT_GT(ma.mean, 0.02) << "quarter " << q << ": the glTF box is dark (its light not honoured?)";
    EXPECT_LT(std::fabs(ma.mean - mb.mean), 4.0 * se)
        << "quarter " << q << ": glTF " << ma.mean << " +- " << ma.se << ", OBJ " << mb.mean << " +- " << mb.se;
  }
}

}  // namespace
}  // namespace caustica
