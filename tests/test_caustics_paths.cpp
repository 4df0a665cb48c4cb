// No light path lost with the photon pass on (issue 19, point 5): light
// that reaches a receiver through glass from the background (a constant
// sky), which no photon carries, stays the path tracer's. A glass sphere on
// a diffuse floor under a bright sky and a small area light, 48 x 32:
// with the photon pass (512 passes) the image and the floor around and
// under the sphere hold the light of path tracing alone (4096 passes)
// within their noise. Dropping the sky seen through the glass from the
// floor would darken that region by far more (the sphere's transmitted sky
// is most of the light there); counting the light's caustic twice would
// brighten it. The table of which estimator counts which path is in
// scenes/FORMAT.md (Caustics).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "host/app/session.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

const char* kGlassUnderSky = R"({"nbounces": 8, "rendermode": "pathtracer",
 "camera": {"type": "pinhole", "width": 48, "height": 32, "position": [0, 1.6, 3.2], "lookAt": [0, 0.4, 0],
            "upVector": [0, 1, 0], "fov": 40},
 "scene": {"backgroundcolor": [0.9, 0.95, 1.0],
  "lightsources": [{"type": "arealight", "position": [1.0, 3.0, 0.5], "u": [0.2, 0, 0], "v": [0, 0, 0.2],
                    "intensity": [40, 40, 40]}],
  "shapes": [
   {"type": "rectangle", "v0": [-3, 0, -3], "v1": [-3, 0, 3], "v2": [3, 0, 3], "v3": [3, 0, -3],
    "material": {"kd": 0.8, "ks": 0.0, "diffusecolor": [0.8, 0.8, 0.8]}},
   {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5,
    "material": {"isrefractive": true, "refractiveindex": 1.5, "diffusecolor": [1, 1, 1],
                 "specularcolor": [1, 1, 1]}}]}})";

ImageF render(const std::string& scene, CausticsMode caustics, int spp, RenderStats* stats) {
  SessionOptions o;
  o.scene_path = scene;
  o.width = int(test::sized(48, 12));           // 12 x 8 on Oclgrind,
  o.photons = uint32_t(test::sized(0, 1024));    // with 1024 photons a map (default: 16384 at least)
  o.device = test::device_spec();
  o.spp = spp;
  o.seed = 7;
  o.caustics = caustics;
  auto s = prepare_session(o);
  EXPECT_EQ(s->features.caustics, caustics == CausticsMode::On);
  const ImageF image = s->renderer->render(stats);
  test::expect_finite_render(image, stats->film, scene);
  return image;
}

// Rows y0..y1, columns x0..x1 (from the top), all channels.
double sum(const ImageF& img, int x0, int x1, int y0, int y1) {
  double s = 0.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      for (int c = 0; c < 3; ++c) s += img.rgb[size_t(3 * (y * img.width + x) + c)];
  return s;
}

TEST(CausticsPaths, SkySeenThroughGlassStaysWithThePathTracer) {
  const std::string scene = test::temp_dir() + "/glass_under_sky.json";
  std::ofstream(scene) << kGlassUnderSky;
  RenderStats on_stats, off_stats;
  const ImageF on = render(scene, CausticsMode::On, int(test::sized(512, 8)), &on_stats);
  const ImageF off = render(scene, CausticsMode::Off, int(test::sized(4096, 32)), &off_stats);
  EXPECT_GT(on_stats.photons_stored, 0u);
  const int w = on.width, h = on.height;
  const double whole = sum(on, 0, w - 1, 0, h - 1) / sum(off, 0, w - 1, 0, h - 1);
  // the sphere and the floor around and under it (columns 16-32, rows 20-31 of 48 x 32)
  const int x0 = w / 3, x1 = 2 * w / 3, y0 = 5 * h / 8;
  const double region = sum(on, x0, x1, y0, h - 1) / sum(off, x0, x1, y0, h - 1);
  std::printf("[measure] with the photon pass / path tracing alone: whole image %.4f, sphere and floor %.4f\n", whole,
              region);
  const double slack = test::on_simulator() ? 8.0 : 1.0;  // a few passes of 96 pixels there
  EXPECT_NEAR(whole, 1.0, 0.01 * slack);
  EXPECT_NEAR(region, 1.0, 0.02 * slack);
}

}  // namespace
}  // namespace caustica
