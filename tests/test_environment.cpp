// Environment lighting (issue 24, part 3): the scene's "environment", an
// equirectangular map (or the Preetham sky written to one) as the sky.
// Maps are made in code and written as PFM files.
// - the file form and its errors (both a background and a map, a missing
//   or broken file, bad sky parameters);
// - the orientation convention (scenes/FORMAT.md): camera rays that miss
//   see the texel the convention names, unrotated and rotated, in phong and
//   path mode;
// - the host-compiled sampling (kernels/lib/lights/environment_light.h):
//   chi-square of sampled directions against the density it reports, and
//   photons that carry the power the light table picks by;
// - renders: a furnace under a constant map equals the constant background;
//   a map with one bright texel lights a floor as a directional light of
//   irradiance (texel radiance x its solid angle's cosine integral), with
//   the shadow along it, as the real directional light ("directional",
//   tests/test_directional_light.cpp) of that irradiance renders it; on a sun 1e5 x the sky, importance sampling's
//   error at equal samples is 10x below BSDF sampling's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "host/app/session.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/lights/environment_light.h"
#include "host/lights/light_types.h"
#include "host/scene/load_scene.h"
#include "host/scene/scene_reader.h"
#include "host/scene/sky_model.h"
#include "kernels/shared/camera.h"
#include "tests/support/chi_square.h"
#include "tests/support/path_render.h"
#include "tests/support/photon_emission.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

constexpr double kPi = 3.14159265358979323846;
using test::write_scene;

// A linear map written as PFM into the test's folder; returns its path.
std::string write_map(const std::string& name, const ImageF& map) {
  const std::string path = test::temp_dir() + "/" + name;
  write_image(path, map, DisplaySettings{});
  return path;
}

ImageF constant_map(int w, int h, float value) { return ImageF(w, h, value); }

// A scene under `environment` (the JSON object's text), with `shapes`.
std::string env_scene(const std::string& environment, const std::string& shapes, const std::string& camera,
                      int nbounces = 1, const char* mode = "pathtracer") {
  return std::string(R"({"nbounces": )") + std::to_string(nbounces) + R"(, "rendermode": ")" + mode +
         R"(", "camera": )" + camera + R"(, "scene": {"environment": )" + environment + R"(, "shapes": [)" + shapes +
         "]}}";
}
std::string file_env(const std::string& path, const std::string& extra = "") {
  return R"({"file": ")" + path + "\"" + extra + "}";
}

const char* kFar = R"({"type": "sphere", "center": [0, 0, -100], "radius": 0.01})";
const char* kLookZ = R"({"type": "pinhole", "width": 32, "height": 32, "position": [0, 0, 0], "lookAt": [0, 0, 1],
  "upVector": [0, 1, 0], "fov": 90})";

std::string load_error(const std::string& text) {
  try {
    load_scene(write_scene("env_bad.json", text));
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Environment, FileFormAndPreciseErrors) {
  const std::string map = write_map("env_const.pfm", constant_map(8, 4, 0.5f));
  const Scene s = load_scene(write_scene("env_ok.json", env_scene(file_env(map, R"(, "intensity": 2, "rotate": [0, 90, 0])"), kFar, kLookZ)));
  ASSERT_TRUE(s.environment.has_value());
  EXPECT_EQ(s.environment->width, 8);
  EXPECT_FLOAT_EQ(s.environment->rgb[5], 1.0f);  // 0.5 x intensity 2
  EXPECT_NEAR(s.environment->rotation[0][2], -1.0f, 1e-6f);  // R (1,0,0) = (0,0,-1) at +90 about y

  const std::string both = std::string(R"({"camera": )") + kLookZ + R"(, "scene": {"backgroundcolor": [1, 1, 1],
    "environment": {"file": ")" + map + R"("}, "shapes": [)" + kFar + "]}}";
  EXPECT_TRUE(test::Contains(load_error(both), {"/scene: expected either \"backgroundcolor\"", "got both"}));
  EXPECT_TRUE(test::Contains(load_error(env_scene(file_env("no_such_sky.hdr"), kFar, kLookZ)),
                             {"/scene/environment/file: expected an existing environment map", "no_such_sky.hdr"}));
  std::ofstream(test::temp_dir() + "/broken.hdr") << "#?RADIANCE\nnot an image";
  EXPECT_TRUE(test::Contains(load_error(env_scene(file_env(test::temp_dir() + "/broken.hdr"), kFar, kLookZ)),
                             {"/scene/environment/file: could not read the environment map", "broken.hdr"}));
  ImageF negative = constant_map(4, 2, 1.0f);
  negative.at(3, 1)[1] = -2.0f;
  EXPECT_TRUE(test::Contains(load_error(env_scene(file_env(write_map("neg.pfm", negative)), kFar, kLookZ)),
                             {"/scene/environment/file: ", "neg.pfm: texel (3, 1): expected finite non-negative radiance"}));
  EXPECT_TRUE(test::Contains(load_error(env_scene(R"({"sky": {"resolution": [8192, 4096]}})", kFar, kLookZ)),
                             {"/scene/environment/sky/resolution: expected [width, height]"}));
  EXPECT_TRUE(test::Contains(load_error(env_scene("{}", kFar, kLookZ)), {"exactly one of \"file\"", "\"sky\""}));
  EXPECT_TRUE(test::Contains(load_error(env_scene(R"({"sky": {"sun_elevation": -5}})", kFar, kLookZ)),
                             {"/scene/environment/sky/sun_elevation: expected degrees above the horizon"}));
  EXPECT_TRUE(test::Contains(load_error(env_scene(R"({"sky": {"turbidity": 40}})", kFar, kLookZ)),
                             {"/scene/environment/sky/turbidity"}));
  EXPECT_TRUE(test::Contains(load_error(env_scene(R"({"sky": {}, "intensity": -1})", kFar, kLookZ)),
                             {"/scene/environment/intensity"}));
}

// `caustica sky` writes the image the "sky" form renders with, texel for
// texel; the sun's power is all in the image (radiance x solid angle).
TEST(Environment, SkyCommandWritesTheSkyTheSceneUses) {
  const std::string out = test::temp_dir() + "/sky.pfm";
  const test::CliResult r =
      test::run_cli("sky --sun-elevation 35 --sun-azimuth 60 --turbidity 4 --width 64 --height 32 -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const Scene s = load_scene(write_scene("env_sky.json", env_scene(R"({"sky": {"sun_elevation": 35, "sun_azimuth": 60,
    "turbidity": 4, "resolution": [64, 32]}})", kFar, kLookZ)));
  const ImageF written = read_hdr_image(out);
  ASSERT_EQ(written.rgb.size(), s.environment->rgb.size());
  EXPECT_EQ(written.rgb, s.environment->rgb);
  SkyParams p;
  p.sun_elevation = 35, p.sun_azimuth = 60, p.turbidity = 4, p.width = 64, p.height = 32;
  p.sun_disk = false;
  const ImageF sky_only = preetham_sky(p);
  float sun[3];
  preetham_sun_radiance(p, sun);
  // The sun's radiance x its solid angle is what the image holds beyond the
  // sky alone, however many texels its 0.53 degrees straddle.
  double added = 0.0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const double solid = 2.0 * kPi / 64 * (std::cos(kPi * y / 32) - std::cos(kPi * (y + 1) / 32));
      added += solid * (double(written.at(x, y)[1]) - sky_only.at(x, y)[1]);
    }
  const double sun_power = sun[1] * 2.0 * kPi * (1.0 - std::cos(kSunAngularRadiusDegrees * kPi / 180.0));
  EXPECT_NEAR(added, sun_power, 1e-4 * sun_power);
  EXPECT_GT(sun[1], 1e4f * sky_only.at(0, 0)[1]);  // the sun's radiance dwarfs the zenith's
  EXPECT_TRUE(test::Contains(test::run_cli("sky --sun-elevation 95 -o " + out).output, {"--sun-elevation"}));
  EXPECT_TRUE(test::Contains(test::run_cli("sky -o " + test::temp_dir() + "/sky.png").output, {"expected a .pfm or .exr"}));
}

using Rendered = test::CameraRender;
Rendered render(const std::string& text, RenderMode mode, int spp) {
  test::CameraRenderOptions o;
  o.spp = spp;
  return test::render_with_camera(write_scene("env_render.json", text), mode, o);
}

// The convention, written independently of the kernels: world direction d,
// turned by R^T (R = Ry(degrees about y)), then u = 1/2 + atan2(x, z) / 2pi,
// v = acos(y) / pi. Returns false near a texel's edge.
bool expected_texel(glm::dvec3 d, double y_degrees, int w, int h, int* x, int* y) {
  d = glm::normalize(d);
  const double a = y_degrees * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  const glm::dvec3 m(c * d.x - s * d.z, d.y, s * d.x + c * d.z);  // Ry^T d
  const double u = 0.5 + std::atan2(m.x, m.z) / (2.0 * kPi), v = std::acos(std::clamp(m.y, -1.0, 1.0)) / kPi;
  const double fu = u * w, fv = v * h;
  if (std::abs(fu - std::round(fu)) < 0.05 || std::abs(fv - std::round(fv)) < 0.05) return false;
  *x = std::min(w - 1, int(fu));
  *y = std::min(h - 1, int(fv));
  return true;
}

TEST(Environment, MissesSeeTheTexelTheConventionNames) {
  const int w = 8, h = 4;
  ImageF map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      map.at(x, y)[0] = float(x + 1);
      map.at(x, y)[1] = float(y + 1);
      map.at(x, y)[2] = 0.25f;
    }
  const std::string path = write_map("env_coded.pfm", map);
  for (const double turn : {0.0, 90.0})
    for (const RenderMode mode : {RenderMode::Phong, RenderMode::Path}) {
      const std::string rotate = ", \"rotate\": [0, " + std::to_string(turn) + ", 0]";
      const Rendered r = render(env_scene(file_env(path, rotate), kFar, kLookZ, 1), mode, 1);
      int checked = 0;
      for (int py = 0; py < r.image.height; ++py)
        for (int px = 0; px < r.image.width; ++px) {
          float d[3];
          camera_plane_point(&r.camera, float(px + 0.5), float(py + 0.5), d);
          int tx, ty;
          if (!expected_texel(glm::dvec3(d[0], d[1], d[2]), turn, w, h, &tx, &ty)) continue;
          // Path mode jitters within the pixel: only pixels well inside a texel.
          const float* p = r.image.at(px, py);
          if (std::abs(p[0] - (tx + 1)) > 1e-4f || std::abs(p[1] - (ty + 1)) > 1e-4f) {
            if (mode == RenderMode::Path) continue;  // a jittered sample crossed the texel's edge
            ADD_FAILURE() << "turn " << turn << " pixel " << px << "," << py << ": got " << p[0] << "," << p[1]
                          << " expected texel " << tx << "," << ty;
          }
          ++checked;
        }
      EXPECT_GT(checked, 600) << "turn " << turn << " mode " << render_mode_name(mode);
    }
}

// A map of the given texels (4 floats each) in the device layout, with its light.
struct HostMap {
  std::vector<float> data;
  Light light{};
};
HostMap host_map(const ImageF& img, glm::vec3 degrees) {
  Scene scene;
  Sphere s{};
  s.center_radius = cs_float4{0, 0, 0, 1};
  scene.spheres.push_back(s);
  scene.environment = make_environment("test map", img.width, img.height, img.rgb, 1.0f, scene_detail::rotation_xyz(degrees));
  HostMap m;
  m.data = environment_device_data(scene);
  m.light = environment_light(scene);
  return m;
}

ImageF sun_and_sky(int w, int h, int sun_x, int sun_y, float sun, float sky) {
  ImageF img(w, h, sky);
  for (int c = 0; c < 3; ++c) img.at(sun_x, sun_y)[c] = sun;
  return img;
}

TEST(Environment, SampledDirectionsFollowTheReportedDensityChiSquare) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  ImageF varied(24, 12);
  for (float& v : varied.rgb) v = std::exp(6.0f * u01(rng) - 3.0f);  // three decades
  const std::vector<std::pair<ImageF, glm::vec3>> maps = {{varied, {20, 30, 40}},
                                                          {sun_and_sky(16, 8, 5, 2, 1e3f, 1.0f), {0, 0, 0}}};
  const uint32_t n = 1u << 21;
  for (const auto& [img, degrees] : maps) {
    const HostMap m = host_map(img, degrees);
    std::vector<cl_float4> samples(n);
    for (uint32_t i = 0; i < n; ++i) {
      float pdf;
      const float3 d = environment_sample_direction(m.data.data(), make_float2(u01(rng), u01(rng)), &pdf);
      samples[i] = pdf > 0.0f ? cl_float4{{d.x, d.y, d.z, 0.0f}} : cl_float4{{0, 0, 0, 0}};
    }
    const test::Density density = [&](const std::vector<cl_float4>& points) {
      std::vector<double> f;
      for (const cl_float4& p : points) {
        const float3 w = normalize(make_float3(p.s[0], p.s[1], p.s[2]));
        f.push_back(environment_light_pdf(m.data.data(), &m.light, w, w, w));
      }
      return f;
    };
    const test::ChiSquare r = test::chi_square_test(samples, test::sphere_domain(), density);
    std::printf("[measure] environment %dx%d: %s\n", img.width, img.height, r.describe().c_str());
    EXPECT_GT(r.p, test::sidak(2)) << r.describe();
    EXPECT_NEAR(r.integral, 1.0, 1e-3) << r.describe();
  }
}

// The light table picks by pi r^2 x the integral of luminance; unguided
// photons carry that flux (Monte Carlo, 5 standard errors).
TEST(Environment, PhotonsCarryThePowerTheTablePicksBy) {
  const HostMap m = host_map(sun_and_sky(16, 8, 3, 2, 50.0f, 0.5f), {0, 45, 0});
  const double r = m.light.p0.w;
  const double power = light_type(LIGHT_ENVIRONMENT).power(m.light);
  EXPECT_NEAR(power, kPi * r * r * m.light.p1.x, 1e-4 * power);
  const int n = 1 << 18;
  double sum = 0.0, sum2 = 0.0;
  int outside = 0;
  test::emit_photons(m.light, m.data.data(), n, 3, [&](float3 origin, float3 dir, float3 flux) {
    // The photon crosses the bounding sphere's centre plane within the radius.
    const float3 to = origin - make_float3(m.light.p0.x, m.light.p0.y, m.light.p0.z);
    const float along = dot(to, dir);
    outside += length(to - along * dir) >= float(r) * 1.0001f;
    const double lum = 0.2126 * flux.x + 0.7152 * flux.y + 0.0722 * flux.z;
    sum += lum;
    sum2 += lum * lum;
  });
  EXPECT_EQ(outside, 0);
  const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, power, 5.0 * se + 1e-4 * power);
}

// A diffuse sphere under a map of constant radiance L reflects what it
// does under backgroundcolor L: the mean over its disc within noise.
TEST(Environment, FurnaceMatchesTheConstantBackground) {
  const int size = int(test::sized(32, 16));
  const std::string camera = R"({"type": "pinhole", "width": )" + std::to_string(size) + R"(, "height": )" +
                             std::to_string(size) + R"(, "position": [0, 0, -4], "lookAt": [0, 0, 0],
    "upVector": [0, 1, 0], "fov": 45})";
  const std::string sphere = R"({"type": "sphere", "center": [0, 0, 0], "radius": 1,
    "material": {"type": "diffuse", "albedo": [0.5, 0.25, 0.75]}})";
  const std::string constant = std::string(R"({"nbounces": 8, "rendermode": "pathtracer", "camera": )") + camera +
                               R"(, "scene": {"backgroundcolor": [0.8, 0.8, 0.8], "shapes": [)" + sphere + "]}}";
  const std::string map = write_map("env_furnace.pfm", constant_map(16, 8, 0.8f));
  const int spp = int(test::sized(64, 4));
  const test::PathRender a = test::render_path(write_scene("furnace_bg.json", constant), spp);
  const test::PathRender b = test::render_path(write_scene("furnace_env.json", env_scene(file_env(map), sphere, camera, 8)), spp);
  auto on_disc = [&](int x, int y) { return std::hypot(x + 0.5 - size / 2.0, y + 0.5 - size / 2.0) < 7.0 * size / 32.0; };
  const test::Mean ma = test::mean_over(a, on_disc), mb = test::mean_over(b, on_disc);
  EXPECT_NEAR(ma.mean, 0.8 * 0.5, 0.01);  // the constant background's furnace is exact
  EXPECT_NEAR(mb.mean, ma.mean, 4.0 * std::hypot(ma.se, mb.se) + 1e-4) << "se " << mb.se;
  EXPECT_NEAR(b.image.at(1, 1)[0], 0.8f, 1e-5f);  // the sky itself
}

// The floor scene for the one-texel and high-dynamic-range tests: a
// Lambertian floor (albedo 0.5) seen from above, optionally a small sphere.
// 32 x 32 pixels, 16 x 16 on Oclgrind.
std::string floor_camera() {
  const std::string size = std::to_string(test::sized(32, 16));
  return R"({"type": "pinhole", "width": )" + size + R"(, "height": )" + size +
         R"(, "position": [0, 6, 0], "lookAt": [0, 0, 0], "upVector": [0, 0, 1], "fov": 60})";
}
const char* kFloor = R"({"type": "rectangle", "v0": [-50, 0, -50], "v1": [-50, 0, 50], "v2": [50, 0, 50], "v3": [50, 0, -50],
  "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}})";

// The irradiance a texel of radiance L gives a floor facing +y: L times the
// integral of cos over the texel's solid angle (unrotated map, y up).
double texel_irradiance(int w, int h, int x, int y, double radiance) {
  const double t0 = kPi * y / h, t1 = kPi * (y + 1) / h;
  // integral over phi of width 2pi/w, over theta of cos t sin t dt
  return radiance * (2.0 * kPi / w) * 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0));
}

TEST(Environment, OneBrightTexelLightsLikeADirectionalLight) {
  const int w = 64, h = 32, sx = 40, sy = 8;
  const std::string map = write_map("env_one_texel.pfm", sun_and_sky(w, h, sx, sy, 1000.0f, 0.0f));
  const std::string blocker = R"({"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
    "material": {"type": "diffuse", "albedo": [0, 0, 0]}},)";
  const std::string scene =
      write_scene("env_sun_floor.json", env_scene(file_env(map), blocker + std::string(kFloor), floor_camera()));
  const int spp = int(test::sized(16, 2));
  const test::PathRender r = test::render_path(scene, spp);
  const int size = r.image.width;
  const CameraGPU camera = camera_for_image(load_scene(scene).camera, size, size);
  const double expected = 0.5 / kPi * texel_irradiance(w, h, sx, sy, 1000.0);
  // The texel's centre direction: the shadow of the sphere at (0, 1, 0)
  // falls on the floor at -(dx, dz) / dy, away from it.
  const double u = (sx + 0.5) / w, v = (sy + 0.5) / h, th = kPi * v, ph = 2.0 * kPi * (u - 0.5);
  const glm::dvec3 to_sun(std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * std::cos(ph));
  const glm::dvec3 shadow = glm::dvec3(0, 1, 0) - to_sun * (1.0 / to_sun.y);
  // The same scene under the directional light of the texel's centre
  // direction whose irradiance on the floor, E cos, is the texel's.
  char light[256];
  const double sun_e = texel_irradiance(w, h, sx, sy, 1000.0) / to_sun.y;
  std::snprintf(light, sizeof light,
                R"({"type": "directional", "direction": [%.9g, %.9g, %.9g], "intensity": [%.9g, %.9g, %.9g]})",
                -to_sun.x, -to_sun.y, -to_sun.z, sun_e, sun_e, sun_e);
  const test::PathRender sun = test::render_path(
      write_scene("dir_sun_floor.json", R"({"nbounces": 1, "rendermode": "pathtracer", "camera": )" + floor_camera() +
                                            R"(, "scene": {"backgroundcolor": [0, 0, 0], "lightsources": [)" + light +
                                            R"(], "shapes": [)" + blocker + kFloor + "]}}"),
      spp);
  int lit = 0, dark = 0;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      float d[3];
      camera_plane_point(&camera, float(px + 0.5), float(py + 0.5), d);
      const glm::dvec3 dir(d[0], d[1], d[2]), o(0, 6, 0);
      const glm::dvec3 p = o + (-6.0 / dir.y) * dir;
      const double from_shadow = glm::length(glm::dvec2(p.x - shadow.x, p.z - shadow.z));
      const double from_sphere = glm::length(glm::dvec2(p.x, p.z));
      const float value = r.image.at(px, py)[1];
      const float directional = sun.image.at(px, py)[1];
      if (from_shadow < 0.3 && from_sphere > 0.8) {
        EXPECT_LT(value, 1e-3 * expected) << "in the shadow at " << px << "," << py;
        EXPECT_EQ(directional, 0.0f) << "in the directional light's shadow at " << px << "," << py;
        ++dark;
      } else if (from_shadow > 1.0 && from_sphere > 0.8) {
        EXPECT_NEAR(value, expected, 0.02 * expected) << px << "," << py;
        // The directional light is exact per sample; the map's texel, a
        // 5.6 x 5.6 degree sun, is sampled: the same within its noise.
        EXPECT_NEAR(directional, expected, 1e-4 * expected) << px << "," << py;
        EXPECT_NEAR(value, directional, 0.02 * directional) << px << "," << py;
        ++lit;
      }
    }
  EXPECT_GE(dark, size == 32 ? 4 : 1);
  EXPECT_GT(lit, size * size / 2);
}

// A sun texel 1e5 x the sky (64 x 32, radiance 1 elsewhere) over a bare
// floor, whose radiance is then 0.5 / pi x (pi x sky + the sun's texel
// irradiance less the sky it replaces) everywhere. At equal samples the
// map's importance sampling (with MIS) has a relMSE at least 10x below
// BSDF sampling alone, which finds the sun with probability ~1e-3, and
// below the map sampled uniformly ("importance": false) with MIS. (Equal
// time: docs/environment.md, bench/environment_benchmark.py.)
TEST(Environment, ImportanceSamplingBeatsBsdfSamplingOnASun) {
  const int w = 64, h = 32, sx = 20, sy = 9;
  const float sun = 1e5f;
  const std::string map = write_map("env_hdr.pfm", sun_and_sky(w, h, sx, sy, sun, 1.0f));
  const std::string scene = write_scene("env_hdr.json", env_scene(file_env(map), kFloor, floor_camera()));
  const double expected = 0.5 / kPi * (kPi + texel_irradiance(w, h, sx, sy, sun - 1.0));
  const std::string uniform =
      write_scene("env_hdr_uniform.json", env_scene(file_env(map, R"(, "importance": false)"), kFloor, floor_camera()));
  const int spp = int(test::sized(8, 2));
  auto rel_mse = [&](uint32_t strategy, const std::string& file = "") {
    test::PathRenderOptions o;
    o.strategy = strategy;
    const test::PathRender r = test::render_path(file.empty() ? scene : file, spp, o);
    double sum = 0.0;
    for (float v : r.image.rgb) sum += (v - expected) * (v - expected) / (expected * expected);
    return sum / double(r.image.rgb.size());
  };
  const double importance = rel_mse(PATH_STRATEGY_MIS), bsdf = rel_mse(PATH_STRATEGY_BSDF),
               uniform_mis = rel_mse(PATH_STRATEGY_MIS, uniform);
  std::printf("[measure] sun 1e5 x sky: relMSE %.3g with importance sampling (MIS), %.3g BSDF only (%.0fx), %.3g "
              "uniform map sampling with MIS (%.0fx)\n",
              importance, bsdf, bsdf / importance, uniform_mis, uniform_mis / importance);
  EXPECT_LT(importance * 10.0, bsdf);
  EXPECT_LT(importance * 10.0, uniform_mis);
  EXPECT_LT(importance, 0.05 / spp);  // measured 0.013 / spp: the sky's share, sampled rarely
}

// The sky's light through a glass sphere onto a floor: the photon pass
// (the map emits photons, and paths light -> caster+ -> receiver that end
// in the sky are the photon map's) and path tracing alone give the same
// image mean within noise (plus 1% for the photon map's kernel bias):
// nothing is counted twice or lost (the photon map carries ~9% of this
// image, so either would move the mean 3x the tolerance). A 3 x 3-texel
// sun of 400 x the sky.
TEST(Environment, PhotonMapAndPathTracingAgreeUnderTheSky) {
  ImageF map(64, 32, 0.5f);
  for (int y = 7; y < 10; ++y)
    for (int x = 38; x < 41; ++x)
      for (int c = 0; c < 3; ++c) map.at(x, y)[c] = 200.0f;
  const std::string path = write_map("env_glass.pfm", map);
  const std::string camera = R"({"type": "pinhole", "width": 32, "height": 32, "position": [0, 4, -1.5],
    "lookAt": [0, 0, 0.3], "upVector": [0, 1, 0], "fov": 50})";
  const std::string shapes = R"({"type": "rectangle", "v0": [-3, 0, -3], "v1": [-3, 0, 3], "v2": [3, 0, 3], "v3": [3, 0, -3],
    "material": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
    {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": {"type": "dielectric", "ior": 1.5}})";
  const std::string scene = write_scene("env_glass.json", env_scene(file_env(path), shapes, camera, 4));
  const int spp = int(test::sized(64, 4));
  test::PathRenderOptions on, off;
  on.caustics = CausticsMode::On;
  off.caustics = CausticsMode::Off;
  const test::PathRender a = test::render_path(scene, spp, on), b = test::render_path(scene, spp, off);
  EXPECT_GT(a.stats.photons_stored, 0u);
  const test::Mean ma = test::mean_all(a), mb = test::mean_all(b);
  std::printf("[measure] sky through glass: image mean %.4f (se %.4f) with the photon pass, %.4f (se %.4f) without\n",
              ma.mean, ma.se, mb.mean, mb.se);
  EXPECT_NEAR(ma.mean, mb.mean, 4.0 * std::hypot(ma.se, mb.se) + 0.01 * mb.mean);
}

}  // namespace
}  // namespace caustica
