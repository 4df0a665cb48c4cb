// The spot light ("type": "spotlight", issue 21): glTF KHR_lights_punctual's
// cone with its smooth falloff, from the scene file to phong, path mode and
// the photon pass.
// - the file form: keys, defaults, and a precise error for each bad value;
// - the host-compiled kernel functions (kernels/lib/lights/spot_light.h):
//   the falloff curve; the power the host picks by (host/lights/
//   spot_light.cpp) is the integral of the intensity over the sphere, and
//   unguided photons carry it (Monte Carlo on the host, 5 standard errors);
// - (the photon pass's emit_photons kernel: tests/test_photon_pass.cpp,
//   PhotonPass.SpotLightPhotonsCarryItsPower);
// - renders of a floor under a spot, phong and path mode, against the
//   closed forms kd I f cos (phong) and (rho / pi) I f cos / d^2 (path);
// - a spot whose inner cone holds the whole scene is the point light:
//   phong bit for bit, path mode and path mode with the photon pass
//   (a glass sphere's caustic) within noise.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "host/app/session.h"
#include "host/error.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "host/scene/load_scene.h"
#include "kernels/shared/camera.h"
#include "tests/support/path_render.h"
#include "tests/support/photon_emission.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

constexpr double kPi = 3.14159265358979323846;

using test::write_scene;

std::string floor_scene(const std::string& light, const std::string& extra_shapes = "", int nbounces = 1) {
  return R"({"nbounces": )" + std::to_string(nbounces) + R"(, "rendermode": "phong",
  "camera": {"type": "pinhole", "width": 48, "height": 48, "position": [0, 4, 0], "lookAt": [0, 0, 0],
             "upVector": [0, 0, 1], "fov": 90},
  "scene": {"backgroundcolor": [0, 0, 0], "ambientlight": [0, 0, 0],
    "lightsources": [)" + light + R"(],
    "shapes": [)" + extra_shapes + R"(
      {"type": "triangle", "v0": [-9, 0, -9], "v1": [9, 0, 9], "v2": [9, 0, -9],
       "material": {"diffusecolor": [0.5, 0.5, 0.5], "kd": 1, "ks": 0, "ka": 0}},
      {"type": "triangle", "v0": [-9, 0, -9], "v1": [-9, 0, 9], "v2": [9, 0, 9],
       "material": {"diffusecolor": [0.5, 0.5, 0.5], "kd": 1, "ks": 0, "ka": 0}}]}})";
}

const char* kSpot = R"({"type": "spotlight", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [4, 4, 4],
  "inner_cone_angle": 20, "outer_cone_angle": 40})";

Light spot(double inner_deg, double outer_deg, glm::vec3 axis = glm::vec3(0, -1, 0)) {
  const std::string text = std::string(R"({"type": "spotlight", "position": [0, 2, 0], "direction": [)") +
                           std::to_string(axis.x) + ", " + std::to_string(axis.y) + ", " + std::to_string(axis.z) +
                           R"(], "intensity": [4, 2, 1], "inner_cone_angle": )" + std::to_string(inner_deg) +
                           R"(, "outer_cone_angle": )" + std::to_string(outer_deg) + "}";
  const Scene s = load_scene(write_scene("spot_one.json", floor_scene(text)));
  return s.lights.at(0);
}

// ------------------------------------------------------------ registries

// The host's registry (host/lights/light_types.cpp) lists the device's
// types (kernels/lib/lights.h's LIGHT_TYPES) in the same order: a kind
// number names the same type on both sides.
TEST(LightTypes, HostRegistryMirrorsTheDevices) {
  const std::vector<LightType>& types = light_types();
  ASSERT_EQ(types.size(), size_t(LIGHT_KIND_COUNT));
  for (uint32_t k = 0; k < types.size(); ++k) {
    EXPECT_EQ(types[k].kind, k);
    EXPECT_NE(types[k].power, nullptr) << "kind " << k;
    // A type read from files shades in phong through its stand-in.
    if (types[k].file_type) EXPECT_NE(types[k].whitted_stand_in, nullptr) << types[k].file_type;
    if (types[k].whitted_stand_in) {
      Light l{};
      l.kind = k;
      EXPECT_TRUE(light_type(types[k].whitted_stand_in(l).kind).delta) << "kind " << k;
    }
    // A delta light has no surface to hit; an area light read from files has geometry.
    if (types[k].delta) EXPECT_EQ(types[k].add_geometry, nullptr) << "kind " << k;
    if (!types[k].delta && types[k].file_type) EXPECT_NE(types[k].add_geometry, nullptr) << types[k].file_type;
  }
  EXPECT_EQ(light_type_of_file("spotlight")->kind, uint32_t(LIGHT_SPOT));
  EXPECT_EQ(light_type_of_file("torch"), nullptr);
}

// ------------------------------------------------------------ file form

TEST(SpotLight, ReadFromTheSceneFile) {
  const Scene s = load_scene(write_scene("spot.json", floor_scene(kSpot)));
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& l = s.lights[0];
  EXPECT_EQ(l.kind, uint32_t(LIGHT_SPOT));
  EXPECT_EQ(to_vec3(l.p0), glm::vec3(0, 2, 0));
  EXPECT_EQ(to_vec3(l.p1), glm::vec3(0, -1, 0));
  EXPECT_FLOAT_EQ(l.p1.w, float(std::cos(40 * kPi / 180)));
  EXPECT_FLOAT_EQ(l.p2.x, float(std::cos(20 * kPi / 180)));
  EXPECT_FLOAT_EQ(l.p2.y, float(1 - std::cos(40 * kPi / 180)));
  EXPECT_EQ(to_vec3(l.emitted), glm::vec3(4));
  EXPECT_TRUE(light_type(l.kind).delta);
  // Phong shades the spot itself.
  const std::vector<Light> whitted = whitted_lights(s);
  ASSERT_EQ(whitted.size(), 1u);
  EXPECT_EQ(whitted[0].kind, uint32_t(LIGHT_SPOT));

  // glTF's defaults: inner 0, outer 45 degrees; the direction is normalised.
  const Scene d = load_scene(write_scene(
      "spot_defaults.json",
      floor_scene(R"({"type": "spotlight", "position": [0, 2, 0], "direction": [0, -3, 0], "intensity": [1, 1, 1]})")));
  EXPECT_EQ(to_vec3(d.lights[0].p1), glm::vec3(0, -1, 0));
  EXPECT_FLOAT_EQ(d.lights[0].p1.w, float(std::cos(kPi / 4)));
  EXPECT_FLOAT_EQ(d.lights[0].p2.x, 1.0f);
}

TEST(SpotLight, BadValuesNameTheirKey) {
  auto error = [](const std::string& light) {
    return test::error_of([&] { load_scene(write_scene("spot_bad.json", floor_scene(light))); });
  };
  const std::string head = R"({"type": "spotlight", "position": [0, 2, 0], "intensity": [1, 1, 1], )";
  EXPECT_TRUE(test::Contains(error(head + R"("direction": [0, 0, 0]})"),
                             {"spot_bad.json", "/scene/lightsources/0/direction", "nonzero length"}));
  EXPECT_TRUE(test::Contains(error(head + R"("direction": [0, -1, 0], "inner_cone_angle": 30, "outer_cone_angle": 30})"),
                             {"/scene/lightsources/0/inner_cone_angle", "below outer_cone_angle"}));
  EXPECT_TRUE(test::Contains(error(head + R"("direction": [0, -1, 0], "outer_cone_angle": 120})"),
                             {"/scene/lightsources/0/outer_cone_angle", "from 0.5 to 90"}));
  EXPECT_TRUE(test::Contains(error(head + R"("direction": [0, -1, 0], "outer_cone_angle": 0.01})"),
                             {"/scene/lightsources/0/outer_cone_angle", "from 0.5 to 90"}));
  EXPECT_TRUE(test::Contains(error(head + R"("direction": [0, -1, 0], "outer_cone_angle": -5})"),
                             {"/scene/lightsources/0/outer_cone_angle"}));
  EXPECT_TRUE(test::Contains(error(R"({"type": "spotlight", "position": [0, 2, 0], "intensity": [1, 1, 1]})"),
                             {"/scene/lightsources/0", "direction"}));
  // The light types the message offers come from the registry.
  EXPECT_TRUE(test::Contains(error(R"({"type": "searchlight"})"), {"\"spotlight\"", "\"pointlight\"", "\"ambient\""}));
}

// ----------------------------------------------- kernel functions, on the host

TEST(SpotLight, FalloffIsGltfsCurve) {
  const Light l = spot(20, 40);
  const double ci = std::cos(20 * kPi / 180), co = std::cos(40 * kPi / 180);
  for (double deg = 0; deg <= 90; deg += 0.5) {
    const double a = deg * kPi / 180;
    const float3 w = make_float3(float(std::sin(a)), float(-std::cos(a)), 0.0f);
    const double c = std::cos(a);
    const double t = std::min(1.0, std::max(0.0, (c - co) / (ci - co)));
    const float3 i = light_intensity_toward(&l, nullptr, w);
    EXPECT_NEAR(i.x, 4.0 * t * t, 2e-5) << deg << " degrees";
    EXPECT_NEAR(i.y, 2.0 * t * t, 2e-5) << deg << " degrees";
  }
  EXPECT_EQ(light_intensity_toward(&l, nullptr, make_float3(0, -1, 0)).x, 4.0f);  // on the axis: I
  EXPECT_EQ(light_intensity_toward(&l, nullptr, make_float3(0, 1, 0)).x, 0.0f);   // behind
}

TEST(SpotLight, PowerIsTheIntegralOfItsIntensity) {
  for (const auto& cone : {std::pair<double, double>{0, 45}, {20, 40}, {0.5, 1.0}, {60, 90}}) {
    const Light l = spot(cone.first, cone.second, glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)));
    // Midpoint rule over cos about the axis (the falloff depends on it alone).
    const glm::dvec3 axis = glm::dvec3(to_vec3(l.p1));
    glm::dvec3 t = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    t = glm::normalize(t - glm::dot(t, axis) * axis);
    const int n = 200000;
    double integral = 0.0;
    for (int k = 0; k < n; ++k) {
      const double c = -1.0 + 2.0 * (k + 0.5) / n, s = std::sqrt(1 - c * c);
      const glm::dvec3 w = c * axis + s * t;
      integral += light_intensity_toward(&l, nullptr, make_float3(float(w.x), float(w.y), float(w.z))).y;
    }
    integral *= 2.0 * kPi * 2.0 / n;  // dw = 2 pi dc
    const double expected = light_type(LIGHT_SPOT).power(l) / luminance(glm::vec3(4, 2, 1)) * 2.0;
    EXPECT_NEAR(integral, expected, 2e-3 * expected + 1e-7) << cone.first << "-" << cone.second << " degrees";
  }
}

TEST(SpotLight, UnguidedPhotonsCarryItsPower) {
  const Light l = spot(10, 35, glm::normalize(glm::vec3(1.0f, -1.0f, 0.5f)));
  const int n = 1 << 18;
  double sum = 0.0, sum2 = 0.0;
  test::emit_photons(l, nullptr, n, 7, [&](float3 origin, float3 dir, float3 flux) {
    EXPECT_EQ(origin.x, 0.0f);
    EXPECT_LE(std::abs(glm::length(glm::vec3(dir.x, dir.y, dir.z)) - 1.0f), 1e-5f);
    // Never outside the outer cone.
    EXPECT_GE(dir.x * l.p1.x + dir.y * l.p1.y + dir.z * l.p1.z, l.p1.w - 1e-6f);
    sum += flux.y;
    sum2 += double(flux.y) * flux.y;
  });
  const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  const double power = light_type(LIGHT_SPOT).power(l) / luminance(glm::vec3(4, 2, 1)) * 2.0;
  std::printf("[measure] spot photons' mean flux %.5f (se %.5f), power %.5f\n", mean, se, power);
  EXPECT_NEAR(mean, power, 5.0 * se);
}

// -------------------------------------------------------------- renders

using Rendered = test::CameraRender;

Rendered render(const std::string& scene_text, RenderMode mode, int spp, CausticsMode caustics = CausticsMode::Off,
                int size = 48) {
  test::CameraRenderOptions o;
  o.spp = spp;
  o.caustics = caustics;
  o.size = size;
  o.seed = 1;
  return test::render_with_camera(test::write_scene("spot_render.json", scene_text), mode, o);
}

// The floor point (y = 0) seen through image position (px, py).
glm::dvec3 floor_point(const CameraGPU& camera, double px, double py) {
  float d[3];
  camera_plane_point(&camera, float(px), float(py), d);
  const glm::dvec3 o(camera.position.x, camera.position.y, camera.position.z), dir(d[0], d[1], d[2]);
  return o + (-o.y / dir.y) * dir;
}

// The spot of floor_scene (kSpot) lighting floor point x: I f(theta) and cos(theta) / d^2.
double spot_falloff_at(glm::dvec3 x, double* cos_theta, double* d2) {
  const glm::dvec3 to = x - glm::dvec3(0, 2, 0);
  *d2 = glm::dot(to, to);
  const double c = -to.y / std::sqrt(*d2);
  *cos_theta = c;
  const double ci = std::cos(20 * kPi / 180), co = std::cos(40 * kPi / 180);
  const double t = std::min(1.0, std::max(0.0, (c - co) / (ci - co)));
  return t * t;
}

TEST(SpotLight, PhongFloorMatchesTheClosedForm) {
  const Rendered r = render(floor_scene(kSpot), RenderMode::Phong, 1);
  int lit = 0, dark = 0;
  for (int py = 0; py < r.image.height; ++py)
    for (int px = 0; px < r.image.width; ++px) {
      double c, d2;
      const double f = spot_falloff_at(floor_point(r.camera, px + 0.5, py + 0.5), &c, &d2);
      const double expected = 0.5 * 4.0 * f * c;  // kd diffusecolor I f cos (phong has no 1 / d^2)
      const float got = r.image.rgb[3 * (size_t(py) * r.image.width + px)];
      ASSERT_NEAR(got, expected, 1e-4 + 1e-4 * expected) << "pixel " << px << ", " << py;
      (f > 0 ? lit : dark)++;
    }
  EXPECT_GT(lit, 200);
  EXPECT_GT(dark, 200);
}

TEST(SpotLight, PathFloorMatchesTheClosedForm) {
  std::string scene = floor_scene(kSpot);
  scene.replace(scene.find("\"phong\""), 7, "\"pathtracer\"");
  // 4 spp on a simulator: the pixel mean of a 4-point pattern misses the
  // falloff's curvature by up to ~7% (Oclgrind measured), 64 by under 3%.
  const int spp = int(test::sized(64, 4));
  const double tolerance = spp >= 64 ? 0.03 : 0.1;
  const Rendered r = render(scene, RenderMode::Path, spp);
  int checked = 0;
  for (int py = 0; py < r.image.height; ++py)
    for (int px = 0; px < r.image.width; ++px) {
      // The pixel's mean over a 6 x 6 grid of its points (a box filter).
      double expected = 0.0;
      bool any_lit = false;
      for (int sy = 0; sy < 6; ++sy)
        for (int sx = 0; sx < 6; ++sx) {
          double c, d2;
          const double f = spot_falloff_at(floor_point(r.camera, px + (sx + 0.5) / 6, py + (sy + 0.5) / 6), &c, &d2);
          expected += 0.5 / kPi * 4.0 * f * c / d2 / 36.0;
          any_lit = any_lit || f > 0.0;
        }
      const float got = r.image.rgb[3 * (size_t(py) * r.image.width + px)];
      // A pixel (~4 degrees seen from the spot here) whose centre lies 5
      // degrees beyond the outer cone gets no light at all.
      double c, d2;
      spot_falloff_at(floor_point(r.camera, px + 0.5, py + 0.5), &c, &d2);
      if (std::acos(c) > (40.0 + 5.0) * kPi / 180) {
        ASSERT_EQ(got, 0.0f) << "pixel " << px << ", " << py << " lies outside the outer cone";
        continue;
      }
      if (!any_lit) continue;  // at the cone's edge, lit in a sliver the grid missed
      // Only the pixel position is random (the light is a delta): a few %
      // where the falloff varies across a pixel, far less elsewhere.
      EXPECT_NEAR(got, expected, tolerance * expected + 2e-4) << "pixel " << px << ", " << py;
      ++checked;
    }
  EXPECT_GT(checked, 200);
}

// A spot whose inner cone (80 degrees) holds everything a light at (0, 2, 0)
// can reach below it sees the scene as the point light does.
TEST(SpotLight, WideSpotIsThePointLight) {
  const char* point = R"({"type": "pointlight", "position": [0, 2, 0], "intensity": [4, 4, 4]})";
  const char* wide = R"({"type": "spotlight", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [4, 4, 4],
    "inner_cone_angle": 89, "outer_cone_angle": 90})";
  // 12^2 pixels and 1 spp on a simulator (six renders of 48^2 took Oclgrind
  // past its 600 s): the two lights trace the same paths, so the bounds
  // below hold at any size.
  const int size = int(test::sized(48, 12));
  // Phong: every shading term the same bits.
  EXPECT_EQ(render(floor_scene(point), RenderMode::Phong, 1, CausticsMode::Off, size).image.rgb,
            render(floor_scene(wide), RenderMode::Phong, 1, CausticsMode::Off, size).image.rgb);
  // Path mode, and with the photon pass: a glass sphere's caustic on the
  // floor. Photons differ (the spot sends none upward), the expectation not.
  const std::string glass =
      R"({"type": "sphere", "center": [0, 0.8, 0], "radius": 0.5,
          "material": {"isrefractive": true, "refractiveindex": 1.5, "kd": 0, "ks": 0}},)";
  for (CausticsMode caustics : {CausticsMode::Off, CausticsMode::On}) {
    std::string a = floor_scene(point, glass, 4), b = floor_scene(wide, glass, 4);
    a.replace(a.find("\"phong\""), 7, "\"pathtracer\"");
    b.replace(b.find("\"phong\""), 7, "\"pathtracer\"");
    const int spp = int(test::sized(64, 1));
    const ImageF x = render(a, RenderMode::Path, spp, caustics, size).image,
                 y = render(b, RenderMode::Path, spp, caustics, size).image;
    double sx = 0, sy = 0, caustic_x = 0, caustic_y = 0;
    for (int py = 0; py < x.height; ++py)
      for (int px = 0; px < x.width; ++px) {
        const size_t i = 3 * (size_t(py) * x.width + px);
        sx += x.rgb[i], sy += y.rgb[i];
        // The caustic: the floor just around the sphere's foot, the middle 40% of the image.
        const double c = 0.5 * (x.width - 1), r = 0.2 * x.width;
        if (std::abs(px - c) < r && std::abs(py - c) < r) caustic_x += x.rgb[i], caustic_y += y.rgb[i];
      }
    std::printf("[measure] %s: point light %.4f, wide spot %.4f (whole image); centre %.4f vs %.4f\n",
                caustics == CausticsMode::On ? "photon pass" : "path tracing", sx, sy, caustic_x, caustic_y);
    EXPECT_NEAR(sy / sx, 1.0, 0.03);
    EXPECT_NEAR(caustic_y / caustic_x, 1.0, 0.05);
  }
}

}  // namespace
}  // namespace caustica
