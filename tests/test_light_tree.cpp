// The light tree in renders (issue 42): next-event estimation through the
// tree (--light-sampler tree), through the power CDF and uniformly gives
// the same image in expectation (on 40 lights of every kind, and on the
// Cornell box); with the tree, MIS, light sampling alone
// and BSDF sampling alone agree; a closed furnace of many emitters gives
// its analytic radiance; and on many lights the tree is less noisy than the
// CDF at equal samples. The tree's own sampling and pmf are tested on the
// host (tests/host/test_light_tree.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/support/path_render.h"

namespace caustica {
namespace {

using test::PathRender;
using test::PathRenderOptions;
using test::render_path;

std::string write_scene(const std::string& name, const std::string& text) {
  const std::string path = test::temp_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A floor and two spheres under `count` lights of every positioned kind
// (rectangles facing down, spheres, points, spots, emissive two-sided
// triangles), with a directional light and the sky when `distant`: the
// tree then hangs under a root that picks the lights at infinity by power.
std::string many_lights_scene(int count, bool distant) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::string lights, shapes;
  auto num = [](float x) { return std::to_string(x); };
  for (int i = 0; i < count; ++i) {
    const float x = -4.0f + 8.0f * u(rng), z = -3.0f + 6.0f * u(rng), y = 2.0f + 0.8f * u(rng);
    const float s = 0.5f + 4.0f * u(rng);
    const std::string pos = "[" + num(x) + ", " + num(y) + ", " + num(z) + "]";
    const std::string rgb = "[" + num(s) + ", " + num(s * u(rng)) + ", " + num(s * u(rng)) + "]";
    std::string l;
    switch (i % 5) {
      case 0:
        l = R"({"type": "arealight", "position": )" + pos + R"(, "intensity": )" + rgb +
            R"(, "size": [0.2, 0.2], "u": [1, 0, 0], "v": [0, 0, 1]})";
        break;
      case 1:
        l = R"({"type": "spherelight", "position": )" + pos + R"(, "radius": 0.05, "intensity": )" + rgb + "}";
        break;
      case 2:
        l = R"({"type": "pointlight", "position": )" + pos + R"(, "intensity": )" + rgb + "}";
        break;
      case 3:
        l = R"({"type": "spotlight", "position": )" + pos + R"(, "direction": [0, -1, 0.2], "intensity": )" + rgb +
            R"(, "inner_cone_angle": 20, "outer_cone_angle": 35})";
        break;
      default: {
        const std::string v0 = "[" + num(x) + ", " + num(y) + ", " + num(z) + "]";
        const std::string v1 = "[" + num(x + 0.3f) + ", " + num(y) + ", " + num(z) + "]";
        const std::string v2 = "[" + num(x) + ", " + num(y - 0.1f) + ", " + num(z + 0.3f) + "]";
        shapes += R"(, {"type": "triangle", "v0": )" + v0 + R"(, "v1": )" + v1 + R"(, "v2": )" + v2 +
                  R"(, "material": {"emission": )" + rgb + R"(, "kd": 0, "twosided": true}})";
        continue;
      }
    }
    lights += (lights.empty() ? "" : ", ") + l;
  }
  if (distant) lights += R"(, {"type": "directional", "direction": [0.3, -1, 0.2], "intensity": [0.5, 0.45, 0.4]})";
  return R"({"nbounces": 3, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 48, "height": 32, "position": [0, 2.2, -6], "lookAt": [0, 0.5, 0],
               "upVector": [0, 1, 0], "fov": 55},
    "scene": {)" +
         std::string(distant ? R"( "environment": {"sky": {"sun_elevation": 40, "turbidity": 3, "resolution": [128, 64]}, "intensity": 0.05},)"
                             : R"( "backgroundcolor": [0, 0, 0],)") +
         R"( "lightsources": [)" + lights + R"(],
      "shapes": [
        {"type": "rectangle", "corner1": [-6, 0, -6], "corner2": [6, 0, 6], "material": {"diffusecolor": [0.7, 0.7, 0.7]}},
        {"type": "sphere", "center": [-1, 0.7, 0.5], "radius": 0.7, "material": {"diffusecolor": [0.8, 0.4, 0.3]}},
        {"type": "sphere", "center": [1.2, 0.5, -0.3], "radius": 0.5,
         "material": {"diffusecolor": [0.3, 0.5, 0.8], "specularcolor": [0.4, 0.4, 0.4], "roughness": 0.25}})" +
         shapes + "]}}";
}

// The image's mean (three channels) and its standard error from the
// film's two halves (tests/support/path_render.h).
struct ImageMean {
  double mean = 0.0, se = 0.0;
};
ImageMean image_mean(const PathRender& r) {
  double sum = 0.0, var = 0.0;
  for (size_t i = 0; i < r.image.rgb.size(); ++i) {
    sum += r.image.rgb[i];
    const double d = r.image.rgb[i] - r.half.rgb[i];
    var += d * d;
  }
  const double n = double(r.image.rgb.size());
  return {sum / n, std::sqrt(var) / n};
}

PathRender render_with(const std::string& scene, int spp, LightSampler sampler, uint32_t strategy = PATH_STRATEGY_MIS) {
  PathRenderOptions o;
  o.light_sampler = sampler;
  o.strategy = strategy;
  o.caustics = CausticsMode::Off;
  o.seed = 3;
  return render_path(scene, spp, o);
}

TEST(LightTreeRender, EverySamplerGivesTheSameImageInExpectation) {
  for (bool distant : {false, true}) {
    if (distant && test::on_simulator()) continue;  // the same walk under one more root node: minutes on Oclgrind
    const std::string scene =
        write_scene(distant ? "many_lights_distant.json" : "many_lights.json", many_lights_scene(40, distant));
    const int spp = int(test::sized(128, 4));
    const ImageMean tree = image_mean(render_with(scene, spp, LightSampler::Tree));
    const ImageMean power = image_mean(render_with(scene, spp, LightSampler::Power));
    const ImageMean uniform = image_mean(render_with(scene, spp, LightSampler::Uniform));
    std::printf("[measure] %s: image mean tree %.5f +- %.5f, power %.5f +- %.5f, uniform %.5f +- %.5f\n",
                distant ? "40 lights, sun and sky" : "40 lights", tree.mean, tree.se, power.mean, power.se,
                uniform.mean, uniform.se);
    EXPECT_NEAR(tree.mean, power.mean, 4.0 * std::hypot(tree.se, power.se));
    EXPECT_NEAR(uniform.mean, power.mean, 4.0 * std::hypot(uniform.se, power.se));
    // Many lights at different distances: the tree is the least noisy.
    if (!test::on_simulator()) EXPECT_LT(tree.se, power.se);
  }
}

// The Cornell box (its light is two emissive triangles: the tree has two
// leaves and picks between them by importance, not by power): the same
// image mean with every sampler.
TEST(LightTreeRender, TheCornellBoxIsTheSameWithEverySampler) {
  const std::string scene = test::source_dir() + "/scenes/cornell_box.json";
  const int spp = int(test::sized(256, 16));
  ImageMean means[3];
  const LightSampler samplers[3] = {LightSampler::Tree, LightSampler::Power, LightSampler::Uniform};
  for (int i = 0; i < 3; ++i) {
    PathRenderOptions o;
    o.light_sampler = samplers[i];
    o.caustics = CausticsMode::Off;
    o.width = o.height = test::on_simulator() ? 8 : 32;
    o.seed = uint32_t(11 + i);  // independent noise
    means[i] = image_mean(render_path(scene, spp, o));
  }
  std::printf("[measure] Cornell box: image mean tree %.5f +- %.5f, power %.5f +- %.5f, uniform %.5f +- %.5f\n",
              means[0].mean, means[0].se, means[1].mean, means[1].se, means[2].mean, means[2].se);
  EXPECT_NEAR(means[0].mean, means[1].mean, 4.0 * std::hypot(means[0].se, means[1].se));
  EXPECT_NEAR(means[2].mean, means[1].mean, 4.0 * std::hypot(means[2].se, means[1].se));
}

TEST(LightTreeRender, MisLightSamplingAndBsdfSamplingAgreeThroughTheTree) {
  // Area lights only (BSDF sampling reaches every light).
  std::string text = many_lights_scene(30, false);
  const std::string scene = write_scene("many_area_lights.json", text);
  const int spp = int(test::sized(256, 4));
  ImageMean m[3];
  const uint32_t strategies[3] = {PATH_STRATEGY_MIS, PATH_STRATEGY_NEE, PATH_STRATEGY_BSDF};
  // Point and spot lights are out of BSDF sampling's reach: compare MIS
  // with light sampling alone on every light, and with BSDF sampling on a
  // scene of area lights (every fifth light kind kept).
  for (int k = 0; k < 2; ++k) m[k] = image_mean(render_with(scene, spp, LightSampler::Tree, strategies[k]));
  std::printf("[measure] 30 lights, tree: MIS %.5f +- %.5f, light sampling %.5f +- %.5f\n", m[0].mean, m[0].se,
              m[1].mean, m[1].se);
  EXPECT_NEAR(m[1].mean, m[0].mean, 4.0 * std::hypot(m[0].se, m[1].se));
  // Rectangles and emissive triangles only.
  std::string area_only;
  {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::string lights;
    // A 6 x 4 grid of rectangles that do not overlap (coplanar emitters
    // that overlap would be seen twice by light sampling, once by rays).
    for (int i = 0; i < 24; ++i) {
      const float x = -3.0f + 1.2f * float(i % 6) + 0.2f * u(rng), z = -2.0f + 1.2f * float(i / 6) + 0.2f * u(rng);
      lights += std::string(i ? ", " : "") + R"({"type": "arealight", "position": [)" + std::to_string(x) + ", 2.2, " +
                std::to_string(z) + R"(], "intensity": [2, 2, 2], "size": [0.5, 0.5], "u": [1, 0, 0], "v": [0, 0, 1]})";
    }
    area_only = R"({"nbounces": 2, "rendermode": "pathtracer",
      "camera": {"type": "pinhole", "width": 32, "height": 24, "position": [0, 1.5, -5], "lookAt": [0, 0.5, 0],
                 "upVector": [0, 1, 0], "fov": 55},
      "scene": {"backgroundcolor": [0, 0, 0], "lightsources": [)" + lights + R"(],
        "shapes": [{"type": "rectangle", "corner1": [-6, 0, -6], "corner2": [6, 0, 6],
                    "material": {"diffusecolor": [0.7, 0.7, 0.7]}},
                   {"type": "sphere", "center": [0, 0.7, 0], "radius": 0.7, "material": {"diffusecolor": [0.8, 0.4, 0.3]}}]}})";
  }
  const std::string area_scene = write_scene("area_lights_only.json", area_only);
  const ImageMean mis = image_mean(render_with(area_scene, spp, LightSampler::Tree, PATH_STRATEGY_MIS));
  const ImageMean bsdf = image_mean(render_with(area_scene, spp, LightSampler::Tree, PATH_STRATEGY_BSDF));
  const ImageMean nee = image_mean(render_with(area_scene, spp, LightSampler::Tree, PATH_STRATEGY_NEE));
  std::printf("[measure] 24 area lights, tree: MIS %.5f +- %.5f, NEE %.5f +- %.5f, BSDF %.5f +- %.5f\n", mis.mean,
              mis.se, nee.mean, nee.se, bsdf.mean, bsdf.se);
  EXPECT_NEAR(bsdf.mean, mis.mean, 4.0 * std::hypot(mis.se, bsdf.se));
  EXPECT_NEAR(nee.mean, mis.mean, 4.0 * std::hypot(mis.se, nee.se));
}

// A closed box whose walls are 192 emissive triangles of radiance L and
// albedo rho, seen from inside: every path sees L at every vertex, so the
// radiance is L (1 + rho + ... + rho^d) for d scattering events.
TEST(LightTreeRender, AFurnaceOfManyEmittersGivesItsAnalyticRadiance) {
  const int grid = 4;
  std::string shapes;
  auto vec = [](float x, float y, float z) {
    return "[" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + "]";
  };
  const float L = 0.5f, rho = 0.5f;
  const std::string material = R"(, "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5], "emission": [0.5, 0.5, 0.5], "twosided": true}})";
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j) {
          auto corner = [&](int a, int b) {
            float p[3];
            p[axis] = side ? 1.0f : -1.0f;
            p[(axis + 1) % 3] = -1.0f + 2.0f * float(i + a) / grid;
            p[(axis + 2) % 3] = -1.0f + 2.0f * float(j + b) / grid;
            return vec(p[0], p[1], p[2]);
          };
          shapes += std::string(shapes.empty() ? "" : ", ") + R"({"type": "triangle", "v0": )" + corner(0, 0) +
                    R"(, "v1": )" + corner(1, 0) + R"(, "v2": )" + corner(1, 1) + material;
          shapes += R"(, {"type": "triangle", "v0": )" + corner(0, 0) + R"(, "v1": )" + corner(1, 1) +
                    R"(, "v2": )" + corner(0, 1) + material;
        }
  const int depth = 12;
  const std::string scene = write_scene("furnace_of_emitters.json", R"({"nbounces": )" + std::to_string(depth) +
                                                                        R"(, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 16, "height": 16, "position": [0.1, 0.2, -0.3], "lookAt": [0.3, 0, 1],
               "upVector": [0, 1, 0], "fov": 60},
    "scene": {"backgroundcolor": [0, 0, 0], "shapes": [)" + shapes + "]}}");
  const double expected = L * (1.0 - std::pow(rho, depth + 1)) / (1.0 - rho);
  for (LightSampler sampler : {LightSampler::Tree, LightSampler::Power}) {
    const PathRender r = render_with(scene, int(test::sized(64, 8)), sampler);
    const ImageMean m = image_mean(r);
    std::printf("[measure] furnace of 192 emitters (%s): %.5f +- %.5f, analytic %.5f\n", light_sampler_name(sampler),
                m.mean, m.se, expected);
    EXPECT_NEAR(m.mean, expected, 4.0 * m.se + 1e-4 * expected);
  }
}

}  // namespace
}  // namespace caustica
