// The photon pass (issue 13) at kernel level, against analytic answers:
// - emitted photons carry the lights' power: their flux sums to it (in
//   luminance exactly, since lights are picked in proportion to it; per
//   channel within the sampling error), for every light type;
// - through a glass slab photons keep their direction, land displaced by the
//   refraction's offset, keep their flux (each Fresnel choice is sampled in
//   proportion to its weight), and arrive in the expected number,
//   (1 - F) / (1 + F) of those that meet the slab;
// - off a mirror they leave by the law of reflection from the light's mirror
//   image, with flux times the mirror's Fresnel reflectance;
// - the photon map is the same for any work-group size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/render/device_scene.h"
#include "host/render/kernel_args.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "host/render/photon_pass.h"
#include "tests/support/photon_emission.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

constexpr double kPi = 3.14159265358979323846;

using test::write_scene;

std::unique_ptr<Session> caustics_session(const std::string& scene, size_t local = 64) {
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  o.mode = RenderMode::Path;
  o.caustics = CausticsMode::On;
  o.width = 8;
  o.height = 8;
  o.local_size = local;
  return prepare_session(o);
}

struct PhotonMap {
  std::vector<Photon> photons;
  uint64_t emitted = 0;
};

// One pass of `count` photons through the session's scene.
PhotonMap trace_photons(Session& s, uint32_t count, size_t local = 64) {
  RenderSettings settings = s.settings;
  settings.photons_per_pass = count;
  StageLauncher launcher(*s.runtime, local);
  const LightTable table = build_light_table(s.scene);
  const DeviceLights lights(s.runtime->context(), table);
  PhotonPass pass(launcher, *s.device_scene, s.program.program, lights, settings);
  pass.trace(nullptr);
  PhotonMap map;
  map.emitted = pass.stats().emitted;
  map.photons.resize(pass.grid().params().photon_count);
  if (!map.photons.empty())
    s.runtime->queue().enqueueReadBuffer(pass.grid().photons(), CL_TRUE, 0, map.photons.size() * sizeof(Photon),
                                         map.photons.data());
  return map;
}

glm::dvec3 d3(const cs_float4& v) { return glm::dvec3(v.x, v.y, v.z); }
glm::dvec3 d3(const cs_packed3& v) { return glm::dvec3(v.x, v.y, v.z); }
double luminance(glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Every light type once: point, rectangle, sphere, one-sided and two-sided
// emissive triangles, an emissive cylinder.
const char* kAllLights = R"({"nbounces": 4, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -6], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [
      {"type": "pointlight", "position": [0, 3, 0], "intensity": [2, 1, 0.5]},
      {"type": "arealight", "position": [0, 4, 0], "u": [1, 0, 0], "v": [0, 0, -0.5], "intensity": [1, 3, 2]}],
    "shapes": [
      {"type": "sphere", "center": [2, 2, 0], "radius": 0.3, "material": {"emission": [4, 4, 1]}},
      {"type": "triangle", "v0": [-2, 1, 0], "v1": [-1, 1, 0], "v2": [-2, 1, 1], "material": {"emission": [1, 2, 3]}},
      {"type": "triangle", "v0": [-2, 2, 0], "v1": [-1, 2, 0], "v2": [-2, 2, 1],
       "material": {"emission": [3, 2, 1], "twosided": true}},
      {"type": "cylinder", "center": [1, -1, 0], "axis": [0, 1, 0], "radius": 0.2, "height": 0.4,
       "material": {"emission": [0.5, 0.5, 2]}},
      {"type": "sphere", "center": [0, -3, 0], "radius": 1,
       "material": {"isrefractive": true, "refractiveindex": 1.5}}]}})";

// emit_photons without casters: n photons from the table's lights; one
// field of each photon record (power, dir, ...).
std::vector<cs_float4> emit_unguided(Session& s, const LightTable& table, uint32_t n, const char* field) {
  return test::emit_photons_on_device(s, table, n, field);
}

TEST(PhotonPass, EmittedFluxSumsToTheLightsPower) {
  auto s = caustics_session(write_scene("lights.json", kAllLights));
  // The lights' power, by hand: point 4 pi I; rectangle pi A L; sphere
  // pi 4 pi r^2 L; triangles pi A L (times 2 when two-sided); cylinder
  // pi (2 pi r 2h + 2 pi r^2) L with h the half height 0.4.
  const glm::dvec3 power = 4 * kPi * glm::dvec3(2, 1, 0.5) + kPi * 0.5 * glm::dvec3(1, 3, 2) +
                           kPi * 4 * kPi * 0.09 * glm::dvec3(4, 4, 1) + kPi * 0.5 * glm::dvec3(1, 2, 3) +
                           2 * kPi * 0.5 * glm::dvec3(3, 2, 1) +
                           kPi * (2 * kPi * 0.2 * 0.8 + 2 * kPi * 0.04) * glm::dvec3(0.5, 0.5, 2);
  // 2^12 photons on Oclgrind: each carries the same luminance, and the
  // channels' bounds are in their standard errors.
  const uint32_t n = uint32_t(test::sized(1u << 20, 1u << 12));
  const LightTable table = build_light_table(s->scene);
  ASSERT_EQ(table.lights.size(), 6u);
  const std::vector<cs_float4> flux = emit_unguided(*s, table, n, "power");
  glm::dvec3 sum(0.0), sum2(0.0);
  for (const cs_float4& f : flux) sum += d3(f), sum2 += d3(f) * d3(f);
  std::printf("[measure] emitted flux %.4f %.4f %.4f, lights' power %.4f %.4f %.4f\n", sum.x, sum.y, sum.z, power.x,
              power.y, power.z);
  EXPECT_NEAR(luminance(sum), luminance(power), 1e-4 * luminance(power));
  for (int c = 0; c < 3; ++c) {
    const double se = std::sqrt(std::max(0.0, sum2[c] - sum[c] * sum[c] / n));  // of the sum
    EXPECT_NEAR(sum[c], power[c], 5.0 * se + 1e-6 * power[c]) << "channel " << c;
  }
}

// A spot light (inner 20, outer 40 degrees): its photons leave within the
// outer cone and their flux sums to its power, 2 pi I ((1 - cos_i) +
// (cos_i - cos_o) / 3) (each photon's flux follows the falloff, so the
// bound is the standard error's).
TEST(PhotonPass, SpotLightPhotonsCarryItsPower) {
  auto s = caustics_session(write_scene("spot.json", R"({"nbounces": 4, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -6], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"backgroundcolor": [0, 0, 0],
      "lightsources": [{"type": "spotlight", "position": [0, 2, 0], "direction": [0, -1, 0],
                        "intensity": [4, 4, 4], "inner_cone_angle": 20, "outer_cone_angle": 40}],
      "shapes": [{"type": "sphere", "center": [0, -3, 0], "radius": 1,
                  "material": {"isrefractive": true, "refractiveindex": 1.5}}]}})"));
  const double ci = std::cos(20 * kPi / 180), co = std::cos(40 * kPi / 180);
  const double power = 2 * kPi * 4 * ((1 - ci) + (ci - co) / 3);
  const uint32_t n = uint32_t(test::sized(1u << 18, 1u << 11));
  const LightTable table = build_light_table(s->scene);
  ASSERT_EQ(table.lights.size(), 1u);
  const std::vector<cs_float4> flux = emit_unguided(*s, table, n, "power"), dir = emit_unguided(*s, table, n, "dir");
  double sum = 0.0, sum2 = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    sum += flux[i].x, sum2 += double(flux[i].x) * flux[i].x;
    ASSERT_LE(dir[i].y, -co + 1e-6) << "photon " << i << " left the outer cone";
  }
  const double se = std::sqrt(std::max(0.0, sum2 - sum * sum / n));  // of the sum
  std::printf("[measure] emit_photons: spot flux %.4f (se %.4f), power %.4f\n", sum, se, power);
  EXPECT_NEAR(sum, power, 5.0 * se);
}

// The environment's photons (issue 24): drawn from the map, from a disk of
// the scene's bounding sphere; they carry the power the table picks by
// (pi r^2 x the map's integral of luminance; a grey map, so every channel).
TEST(PhotonPass, EnvironmentPhotonsCarryItsPower) {
  ImageF map(16, 8, 0.25f);
  for (int c = 0; c < 3; ++c) map.at(11, 2)[c] = 40.0f;
  const std::string map_path = test::temp_dir() + "/photon_sky.pfm";
  write_image(map_path, map, DisplaySettings{});
  auto s = caustics_session(write_scene("sky.json", R"({"nbounces": 4, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -6], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"environment": {"file": ")" + map_path + R"(", "rotate": [10, 20, 30]},
      "shapes": [{"type": "sphere", "center": [0, -3, 0], "radius": 1,
                  "material": {"isrefractive": true, "refractiveindex": 1.5}}]}})"));
  const LightTable table = build_light_table(s->scene);
  ASSERT_EQ(table.lights.size(), 1u);
  const Light& sky = table.lights[0];
  const double power = light_type(LIGHT_ENVIRONMENT).power(sky);
  const uint32_t n = uint32_t(test::sized(1u << 18, 1u << 11));
  const std::vector<cs_float4> flux = emit_unguided(*s, table, n, "power"), dir = emit_unguided(*s, table, n, "dir"),
                               origin = emit_unguided(*s, table, n, "origin");
  double sum = 0.0, sum2 = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    sum += flux[i].x, sum2 += double(flux[i].x) * flux[i].x;
    // It crosses the bounding sphere (centre (0, -3, 0), radius ~1) heading in.
    const glm::dvec3 o(origin[i].x, origin[i].y - (-3.0), origin[i].z), d(dir[i].x, dir[i].y, dir[i].z);
    ASSERT_LT(glm::dot(o, d), 0.0) << "photon " << i << " dir " << d.x << "," << d.y << "," << d.z << " flux " << flux[i].x << " origin " << o.x << "," << o.y << "," << o.z;
    ASSERT_LT(glm::length(o - glm::dot(o, d) * d), 1.01 * sky.p0.w) << "photon " << i;
  }
  const double se = std::sqrt(std::max(0.0, sum2 - sum * sum / n));
  std::printf("[measure] emit_photons: environment flux %.4f (se %.4f), power %.4f\n", sum, se, power);
  EXPECT_NEAR(sum, power, 5.0 * se + 1e-4 * power);
}

// A directional light's photons (emit_photons on the device): each
// travels along its direction from outside the scene's bounding sphere,
// crossing that sphere's disk, and carries E pi R^2 / n, so that they sum
// to the power the table picks it by.
TEST(PhotonPass, DirectionalLightPhotonsCarryItsPower) {
  auto s = caustics_session(write_scene("sun.json", R"({"nbounces": 4, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 0, -6], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"backgroundcolor": [0, 0, 0],
      "lightsources": [{"type": "directional", "direction": [1, -2, 0.5], "intensity": [3, 3, 3]}],
      "shapes": [{"type": "sphere", "center": [0, -3, 0], "radius": 1,
                  "material": {"isrefractive": true, "refractiveindex": 1.5}}]}})"));
  const LightTable table = build_light_table(s->scene);
  ASSERT_EQ(table.lights.size(), 1u);
  const Light& sun = table.lights[0];
  ASSERT_EQ(sun.kind, uint32_t(LIGHT_DIRECTIONAL));
  const double r = sun.p0.w, power = 3.0 * kPi * r * r;
  EXPECT_NEAR(r, 1.001 * std::sqrt(3.0), 1e-5);  // the sphere's bounding box's half diagonal
  EXPECT_NEAR(light_type(LIGHT_DIRECTIONAL).power(sun), power, 1e-5 * power);
  const uint32_t n = uint32_t(test::sized(1u << 16, 1u << 10));
  const std::vector<cs_float4> flux = emit_unguided(*s, table, n, "power"), dir = emit_unguided(*s, table, n, "dir"),
                               origin = emit_unguided(*s, table, n, "origin");
  const glm::dvec3 d = glm::normalize(glm::dvec3(1, -2, 0.5));
  double sum = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    sum += flux[i].x;
    ASSERT_NEAR(flux[i].x, power / n, 1e-5 * power / n) << "photon " << i;
    ASSERT_NEAR(glm::length(glm::dvec3(dir[i].x, dir[i].y, dir[i].z) - d), 0.0, 1e-6) << "photon " << i;
    const glm::dvec3 o(origin[i].x, origin[i].y - (-3.0), origin[i].z);
    ASSERT_GT(glm::length(o), r) << "photon " << i << " starts inside the scene";
    ASSERT_LT(glm::dot(o, d), 0.0) << "photon " << i;
    ASSERT_LT(glm::length(o - glm::dot(o, d) * d), 1.0001 * r) << "photon " << i;
  }
  std::printf("[measure] emit_photons: directional flux %.4f, power %.4f\n", sum, power);
  EXPECT_NEAR(sum, power, 1e-4 * power);
}

// Fresnel reflectance of an unpolarised dielectric interface, in double.
double fresnel(double cos_i, double eta) {
  const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t), rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// A point light 1 above a glass slab (y in [0.5, 1], index 1.5) over a
// diffuse floor at y = 0, all 100 wide. Photons steeper than cos 0.3
// are judged: shallower ones may leave the slab's sides, and each surface
// they leave moves them by the ray offset (which scales with the size of
// the slab's triangles) times tan(theta), blurring the landing point.
const char* kSlab = R"({"nbounces": 64, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 5, 5], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [{"type": "pointlight", "position": [0, 2, 0], "intensity": [1, 1, 1]}],
    "shapes": [
      {"type": "box", "min": [-50, 0.5, -50], "max": [50, 1, 50],
       "material": {"isrefractive": true, "refractiveindex": 1.5}},
      {"type": "rectangle", "v0": [-50, 0, -50], "v1": [-50, 0, 50], "v2": [50, 0, 50],
       "v3": [50, 0, -50], "material": {"kd": 0.8, "diffusecolor": [1, 1, 1]}}]}})";

TEST(PhotonPass, GlassSlabKeepsDirectionAndFluxAtFresnelRates) {
  auto s = caustics_session(write_scene("slab.json", kSlab));
  // 2^12 photons on Oclgrind; the count's bound is in its binomial sd.
  const uint32_t n = uint32_t(test::sized(1u << 20, 1u << 12));
  const PhotonMap map = trace_photons(*s, n);
  const double flux = 4.0 * kPi / n;  // a point light of intensity 1, per photon
  size_t direct = 0, steep = 0, off_course = 0;
  for (const Photon& ph : map.photons) {
    const glm::dvec3 wi = d3(ph.wi), x = d3(ph.position);
    ASSERT_NEAR(x.y, 0.0, 1e-3);
    EXPECT_NEAR(ph.power.x, flux, 1e-5 * flux);
    // Straight down from the light at height 2: 1.5 tan(theta) outside the
    // glass plus 0.5 tan(theta_t) through it per crossing (1, 3, 5, ...).
    const double cos_i = wi.y, sin_i = std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
    if (cos_i < 0.3) continue;
    ++steep;
    if (sin_i < 1e-3) continue;  // no horizontal direction to check
    const double tan_i = sin_i / cos_i, sin_t = sin_i / 1.5, tan_t = sin_t / std::sqrt(1.0 - sin_t * sin_t);
    const glm::dvec2 along = -glm::dvec2(wi.x, wi.z) / sin_i;  // horizontal direction of travel
    const glm::dvec2 h(x.x, x.z);
    const double distance = glm::length(h);
    EXPECT_GT(glm::dot(h, along), 0.999 * distance) << "landed off the photon's vertical plane";
    const double crossings = (distance - 1.5 * tan_i) / (0.5 * tan_t);
    // An odd number of crossings (in, and out after 2k inner reflections).
    if (std::abs(crossings - std::round(crossings)) > 2e-2 * std::max(1.0, crossings) ||
        int(std::round(crossings)) % 2 != 1)
      ++off_course;
    direct += std::round(crossings) == 1;
  }
  // Of the photons sent down (half of them, uniform in cos theta), a share
  // T = (1 - F)^2 sum F^2k = (1 - F) / (1 + F) reaches the floor.
  double expected = 0.0;
  const int steps = 200000;
  for (int k = 0; k < steps; ++k) {
    const double mu = 0.3 + 0.7 * (k + 0.5) / steps, f = fresnel(mu, 1.5);
    expected += 0.7 * (1.0 - f) / (1.0 + f) / steps;
  }
  expected *= 0.5 * n;
  const double sd = std::sqrt(expected * (1.0 - expected / n));
  std::printf("[measure] slab: %zu photons steeper than cos 0.3 on the floor (%zu crossed once), expected %.0f +- %.0f\n",
              steep, direct, expected, sd);
  EXPECT_NEAR(double(steep), expected, 4.0 * sd);
  EXPECT_GT(direct, steep * 95 / 100);
  // A few land near a triangle edge of the slab, where the offset blurs them.
  EXPECT_LE(off_course, steep / 10000) << off_course << " photons off their refracted course";
}

// A point light 1 above a horizontal mirror (Schlick reflectance from 0.6
// at normal incidence), under a diffuse ceiling at y = 3.
const char* kMirror = R"({"nbounces": 8, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 8, "height": 8, "position": [0, 1, 5], "lookAt": [0, 1, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [{"type": "pointlight", "position": [0, 1, 0], "intensity": [1, 1, 1]}],
    "shapes": [
      {"type": "rectangle", "v0": [-1000, 0, -1000], "v1": [-1000, 0, 1000], "v2": [1000, 0, 1000],
       "v3": [1000, 0, -1000], "material": {"isreflective": true, "reflectivity": 0.6, "specularcolor": [1, 1, 1]}},
      {"type": "rectangle", "v0": [-1000, 3, -1000], "v1": [1000, 3, -1000], "v2": [1000, 3, 1000],
       "v3": [-1000, 3, 1000], "material": {"kd": 0.8, "diffusecolor": [1, 1, 1]}}]}})";

TEST(PhotonPass, MirrorReflectsFromTheLightsImageWithFresnelFlux) {
  auto s = caustics_session(write_scene("mirror.json", kMirror));
  const uint32_t n = uint32_t(test::sized(1u << 18, 1u << 12));
  const PhotonMap map = trace_photons(*s, n);
  const double flux = 4.0 * kPi / n;
  const glm::dvec3 image(0.0, -1.0, 0.0);  // the light mirrored in y = 0
  for (const Photon& ph : map.photons) {
    const glm::dvec3 wi = d3(ph.wi), x = d3(ph.position);
    ASSERT_NEAR(x.y, 3.0, 1e-3);
    // It came straight from the image: x - image is along -wi.
    EXPECT_LT(glm::length(glm::cross(glm::normalize(x - image), -wi)), 1e-3);
    const double cos_theta = -wi.y, m = 1.0 - cos_theta;  // the angle at the mirror
    EXPECT_NEAR(ph.power.x, flux * (0.6 + 0.4 * m * m * m * m * m), 1e-4 * flux);
  }
  // Every downward photon reaches the ceiling but for grazing ones; at
  // Oclgrind's 2^12 photons 1% is 1.3 binomial sd, so never under 4 sd.
  EXPECT_NEAR(double(map.photons.size()), 0.5 * n, std::max(0.01 * n, 4.0 * 0.5 * std::sqrt(double(n))));
}

TEST(PhotonPass, SamePhotonMapForAnyWorkGroupSize) {
  const std::string scene = write_scene("slab.json", kSlab);
  std::vector<std::vector<Photon>> maps;
  for (size_t local : {1, 16, 64}) {
    auto s = caustics_session(scene, local);
    maps.push_back(trace_photons(*s, uint32_t(test::sized(1u << 16, 1u << 11)), local).photons);
  }
  for (size_t k = 1; k < maps.size(); ++k) {
    ASSERT_EQ(maps[k].size(), maps[0].size());
    EXPECT_EQ(0, std::memcmp(maps[k].data(), maps[0].data(), maps[0].size() * sizeof(Photon))) << "map " << k;
  }
}

}  // namespace
}  // namespace caustica
