// The environment's photons in phong mode (issue 24, the rest of part 3):
// with --caustics on, phong's photon pass emits from the sky as path
// mode's does (the same light-table entry: power pi r^2 int L dw, photons
// through a disk of the casters' bounding sphere), and its gather reflects
// the sky's caustic irradiance E as kd diffuse E / pi (lib/caustics.h).
// Phong has no direct light from the sky, so its caustic is light it did
// not have: the sky focused by a glass sphere onto a diffuse floor.
//
// One scene, a glass sphere on a Lambertian floor under a grey sky with a
// small sun (docs/environment.md, "Phong"), rendered four times:
// - phong without and with the photon pass: their difference is phong's
//   caustic image, never negative (gathers only add), concentrated in a
//   focus;
// - path mode with the photon pass: its caustic image (the separate,
//   per-pixel SPPM estimate: the image less the film's passes) holds the
//   same flux as phong's within a few percent, with its centroid at the
//   same place (the same photons, gathered by another estimator);
// - path mode without the photon pass less the film's passes of the render
//   with it: the path tracer's own estimate of the same caustic paths
//   (light -> caster+ -> receiver, seen directly or through glass), which
//   phong's total matches within noise plus 5% (the radii's blur and
//   phong's pixel centres against path mode's jittered samples).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/app/session.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/render/renderer.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

// The scene in `mode` ("phong" or "pathtracer"): a 64 x 32 sky of 0.5 with
// a 3 x 3-texel sun of 200 about 45 degrees from the zenith, a glass sphere
// (radius 0.6) standing on a floor of diffuse 0.6 (kd 1, ks 0: Lambertian
// in path mode, kd diffuse in phong), seen from above at 32 x 32.
std::string sky_glass_scene(const std::string& mode) {
  ImageF map(64, 32, 0.5f);
  for (int y = 7; y < 10; ++y)
    for (int x = 38; x < 41; ++x)
      for (int c = 0; c < 3; ++c) map.at(x, y)[c] = 200.0f;
  const std::string map_path = test::temp_dir() + "/phong_sky.pfm";
  write_image(map_path, map, DisplaySettings{});
  const std::string size = std::to_string(test::sized(32, 12));
  return R"({"nbounces": 6, "rendermode": ")" + mode + R"(",
  "camera": {"type": "pinhole", "width": )" + size + R"(, "height": )" + size + R"(, "position": [0, 4, -1.5],
             "lookAt": [0, 0, 0.3], "upVector": [0, 1, 0], "fov": 50},
  "scene": {"environment": {"file": ")" + map_path + R"("}, "ambientlight": [0, 0, 0],
    "shapes": [
      {"type": "rectangle", "v0": [-3, 0, -3], "v1": [-3, 0, 3], "v2": [3, 0, 3], "v3": [3, 0, -3],
       "material": {"diffusecolor": [0.6, 0.6, 0.6], "kd": 1, "ks": 0, "ka": 0}},
      {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6,
       "material": {"isrefractive": true, "refractiveindex": 1.5, "kd": 0, "ks": 0}}]}})";
}

struct Render {
  ImageF image;      // what the renderer returns
  ImageF passes;     // the film's passes alone (without the photon pass's separate estimate)
  double passes_se;  // the standard error of `passes`' image sum (the half-buffer difference)
  RenderStats stats;
};

Render render(const std::string& scene_text, RenderMode mode, CausticsMode caustics, int spp) {
  SessionOptions o;
  o.scene_path = test::write_scene("phong_sky.json", scene_text);
  o.device = test::device_spec();
  o.mode = mode;
  o.spp = spp;
  o.caustics = caustics;
  if (test::on_simulator()) o.photons = 1024;
  auto s = prepare_session(o);
  RenderSettings settings = s->settings;
  settings.half_buffer = mode == RenderMode::Path && spp >= 2;
  Renderer r(*s->runtime, *s->device_scene, s->mode, s->program.program, settings);
  Render out;
  out.image = r.render(&out.stats);
  test::expect_finite_render(out.image, out.stats.film, o.scene_path);
  r.film().set_separate_estimate(nullptr);
  out.passes = r.film().mean();
  out.passes_se = 0.0;
  if (settings.half_buffer) {  // path_render.h: sum (M - B)^2 over the values is the sum's variance
    const ImageF half = r.film().half_mean();
    double var = 0.0;
    for (size_t i = 0; i < half.rgb.size(); ++i) var += double(out.passes.rgb[i] - half.rgb[i]) * (out.passes.rgb[i] - half.rgb[i]);
    out.passes_se = std::sqrt(var);
  }
  return out;
}

// a - b per value, and its sum and centroid (x, y) weighted by the values.
struct Difference {
  ImageF image;
  double sum = 0.0, cx = 0.0, cy = 0.0, least = 0.0;
};
Difference difference(const ImageF& a, const ImageF& b) {
  Difference d;
  d.image = ImageF(a.width, a.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = double(a.at(x, y)[c]) - double(b.at(x, y)[c]);
        d.image.at(x, y)[c] = float(v);
        d.sum += v;
        d.cx += v * (x + 0.5);
        d.cy += v * (y + 0.5);
        d.least = std::min(d.least, v);
      }
  if (d.sum > 0.0) d.cx /= d.sum, d.cy /= d.sum;
  return d;
}

TEST(PhongSkyCaustics, GlassFocusesTheSkyAsThePathTracerDoes) {
  const std::string phong = sky_glass_scene("phong"), path = sky_glass_scene("pathtracer");
  const int passes = int(test::sized(16, 2)), spp = int(test::sized(64, 2));
  const Render phong_off = render(phong, RenderMode::Phong, CausticsMode::Off, 1);
  const Render phong_on = render(phong, RenderMode::Phong, CausticsMode::On, passes);
  const Render path_on = render(path, RenderMode::Path, CausticsMode::On, spp);
  const Render path_off = render(path, RenderMode::Path, CausticsMode::Off, spp);

  // Phong's caustic: only added light (the film's fixed point rounds each
  // pass's equal terms alike: a few ulps of 2^-44 at most).
  const Difference caustic = difference(phong_on.image, phong_off.image);
  EXPECT_GE(caustic.least, -1e-6);
  // The path-mode photon map's caustic at the first receiver, and the path
  // tracer's own (with the photon pass, the film's passes leave exactly
  // these paths to the map; its inline gathers at later receivers stay in
  // them and estimate what path tracing finds there).
  const Difference sppm = difference(path_on.image, path_on.passes);
  const Difference traced = difference(path_off.passes, path_on.passes);
  const double traced_se = std::hypot(path_off.passes_se, path_on.passes_se);
  const int width = phong_on.image.width;
  std::printf("[measure] sky caustic through glass (%d^2 pixels, sums over pixels and channels): phong %.4f at "
              "(%.2f, %.2f), path-mode photon map %.4f at (%.2f, %.2f), path tracing %.4f (se %.4f)\n",
              width, caustic.sum, caustic.cx, caustic.cy, sppm.sum, sppm.cx, sppm.cy, traced.sum, traced_se);
  ASSERT_GT(caustic.sum, 0.0);
  ASSERT_GT(sppm.sum, 0.0);
  if (test::on_simulator()) return;  // a dozen pixels and two passes: the kernels ran, no statistics

  // Same photons, another estimator: the same flux (5%: both gathers blur
  // the focus over a radius of about a pixel, at the image's edges too)
  // and the same place (within a pixel).
  EXPECT_NEAR(caustic.sum, sppm.sum, 0.05 * sppm.sum);
  EXPECT_NEAR(caustic.cx, sppm.cx, 1.0);
  EXPECT_NEAR(caustic.cy, sppm.cy, 1.0);
  // The path tracer's estimate of the same paths: within 4 standard errors
  // plus 5%.
  EXPECT_NEAR(caustic.sum, traced.sum, 4.0 * traced_se + 0.05 * traced.sum);
  // A focus: half the caustic's flux within 3 pixels of its centroid, where
  // the floor is brighter with the photons than without by over 20 times
  // the caustic's mean over the image (measured: 22.5, 135 times).
  double near = 0.0;
  for (int y = 0; y < width; ++y)
    for (int x = 0; x < width; ++x)
      if (std::hypot(x + 0.5 - caustic.cx, y + 0.5 - caustic.cy) < 3.0)
        for (int c = 0; c < 3; ++c) near += caustic.image.at(x, y)[c];
  EXPECT_GT(near, 0.5 * caustic.sum);
  const int fx = int(caustic.cx), fy = int(caustic.cy);
  std::printf("[measure] at the focus (%d, %d): phong %.4f with the photon pass, %.4f without\n", fx, fy,
              phong_on.image.at(fx, fy)[1], phong_off.image.at(fx, fy)[1]);
  const double mean = caustic.sum / (3.0 * width * width);
  EXPECT_GT(phong_on.image.at(fx, fy)[1], phong_off.image.at(fx, fy)[1] + 20.0 * mean)
      << "at the focus " << fx << "," << fy;
}

}  // namespace
}  // namespace caustica
