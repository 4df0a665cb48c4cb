// The directional light ("type": "directional"; glTF KHR_lights_punctual's
// directional): a delta light at infinity, irradiance E along one direction.
// - the file form and a precise error per bad value;
// - the host-compiled kernel functions (kernels/lib/lights/
//   directional_light.h): next-event estimation's direction, value and
//   shadow point past the scene; the table's power luminance(E) pi R^2 with
//   R the scene's bounding radius, which every photon carries (its
//   direction is fixed: each photon alike, starting outside the scene and
//   crossing the bounding sphere's disk uniformly);
// - (emit_photons on the device: tests/test_photon_pass.cpp,
//   PhotonPass.DirectionalLightPhotonsCarryItsPower; the map texel that
//   lights as this light does: tests/test_environment.cpp,
//   Environment.OneBrightTexelLightsLikeADirectionalLight; glTF's
//   directional light: tests/test_gltf.cpp);
// - renders of a floor against closed forms: path mode (rho / pi) E cos,
//   exact per sample (a delta light: next-event estimation only), 0 for a
//   light from below; phong's Blinn-Phong E (kd diffuse cos + ks specular
//   lobe) per pixel; a sharp shadow; the photon pass's caustic under a
//   glass ball (its flux against a ray-traced estimate).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/error.h"
#include "host/image/image_io.h"
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

// A floor 18 wide at y = 0 seen from 4 above (every pixel is floor), under
// `light`; `material` is the floor's. 32 x 32 pixels.
std::string floor_scene(const std::string& light, const char* mode, const std::string& material,
                        const std::string& extra_shapes = "") {
  const std::string tri = R"(, "material": )" + material + "}";
  return std::string(R"({"nbounces": 1, "rendermode": ")") + mode + R"(",
  "camera": {"type": "pinhole", "width": 32, "height": 32, "position": [0, 4, 0], "lookAt": [0, 0, 0],
             "upVector": [0, 0, 1], "fov": 90},
  "scene": {"backgroundcolor": [0, 0, 0], "ambientlight": [0, 0, 0],
    "lightsources": [)" + light + R"(],
    "shapes": [)" + extra_shapes +
         R"({"type": "triangle", "v0": [-9, 0, -9], "v1": [9, 0, 9], "v2": [9, 0, -9])" + tri + "," +
         R"({"type": "triangle", "v0": [-9, 0, -9], "v1": [-9, 0, 9], "v2": [9, 0, 9])" + tri + "]}}";
}

const char* kDiffuse = R"({"type": "diffuse", "albedo": [0.5, 0.25, 0.75]})";

std::string directional(glm::dvec3 d, glm::dvec3 e) {
  char buf[256];
  std::snprintf(buf, sizeof buf, R"({"type": "directional", "direction": [%.9g, %.9g, %.9g], "intensity": [%.9g, %.9g, %.9g]})",
                d.x, d.y, d.z, e.x, e.y, e.z);
  return buf;
}

// Travelling down, tilted by theta from -y toward +x.
glm::dvec3 tilted(double theta_deg) {
  const double t = theta_deg * kPi / 180;
  return {std::sin(t), -std::cos(t), 0.0};
}

// ------------------------------------------------------------ file form

TEST(DirectionalLight, ReadFromTheSceneFile) {
  const Scene s = load_scene(write_scene("dir.json", floor_scene(directional({0, -3, 4}, {2, 3, 4}), "phong", kDiffuse)));
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& l = s.lights[0];
  EXPECT_EQ(l.kind, uint32_t(LIGHT_DIRECTIONAL));
  EXPECT_TRUE(light_type(l.kind).delta);
  EXPECT_EQ(light_type_of_file("directional")->kind, uint32_t(LIGHT_DIRECTIONAL));
  EXPECT_NEAR(l.p1.x, 0.0f, 1e-7f);
  EXPECT_NEAR(l.p1.y, -0.6f, 1e-7f);  // normalised
  EXPECT_NEAR(l.p1.z, 0.8f, 1e-7f);
  EXPECT_EQ(to_vec3(l.emitted), glm::vec3(2, 3, 4));
  // The tables give it the scene's bounding sphere (the floor's: centre 0,
  // radius just over 9 sqrt 2) and pick it by luminance(E) pi R^2.
  const cs_float4 bounds = scene_bounding_sphere(s);
  EXPECT_NEAR(bounds.w, 1.001 * 9 * std::sqrt(2.0), 1e-4);
  for (const std::vector<Light>& table : {whitted_lights(s), build_light_table(s).lights}) {
    ASSERT_EQ(table.size(), 1u);
    EXPECT_EQ(table[0].kind, uint32_t(LIGHT_DIRECTIONAL));
    EXPECT_EQ(table[0].p0.w, bounds.w);
    EXPECT_EQ(table[0].p0.x, bounds.x);
    EXPECT_EQ(to_vec3(table[0].p1), to_vec3(l.p1));
  }
  const Light placed = whitted_lights(s)[0];
  EXPECT_NEAR(light_type(LIGHT_DIRECTIONAL).power(placed), kPi * bounds.w * bounds.w * luminance(glm::vec3(2, 3, 4)),
              1e-5 * light_type(LIGHT_DIRECTIONAL).power(placed));
}

TEST(DirectionalLight, BadValuesNameTheirKey) {
  auto error = [](const std::string& light) {
    return test::error_of([&] { load_scene(write_scene("dir_bad.json", floor_scene(light, "phong", kDiffuse))); });
  };
  EXPECT_TRUE(test::Contains(error(R"({"type": "directional", "direction": [0, 0, 0], "intensity": [1, 1, 1]})"),
                             {"dir_bad.json", "/scene/lightsources/0/direction", "nonzero length"}));
  EXPECT_TRUE(test::Contains(error(R"({"type": "directional", "direction": [0, -1, 0]})"),
                             {"dir_bad.json", "/scene/lightsources/0", "intensity"}));
  EXPECT_TRUE(test::Contains(error(R"({"type": "directional", "intensity": [1, 1, 1]})"),
                             {"/scene/lightsources/0", "direction"}));
  EXPECT_TRUE(test::Contains(error(R"({"type": "directional", "direction": [0, -1, 0], "intensity": [1, -1, 1]})"),
                             {"/scene/lightsources/0/intensity"}));
  // The light types the message offers come from the registry.
  EXPECT_TRUE(test::Contains(error(R"({"type": "sun"})"), {"\"directional\"", "\"spotlight\""}));
}

// Issue 38: a direction of any magnitude a float holds is a direction
// ([1e30, -1e30, 0] overflowed when normalised in float, and the scene
// rendered unlit); a scene so large that the light's power overflows is
// refused with the reason, never rendered dark or failed inside.
TEST(DirectionalLight, DirectionsOfAnyMagnitudeAndScenesTooLargeForItsPower) {
  const Scene unit = load_scene(write_scene("dir_unit.json", floor_scene(directional({1, -1, 0}, {1, 1, 1}), "phong", kDiffuse)));
  for (const glm::dvec3& d : {glm::dvec3(1e30, -1e30, 0), glm::dvec3(1e-30, -1e-30, 0), glm::dvec3(3e38, -3e38, 0)}) {
    const Scene s = load_scene(write_scene("dir_scaled.json", floor_scene(directional(d, {1, 1, 1}), "phong", kDiffuse)));
    EXPECT_EQ(to_vec3(s.lights.at(0).p1), to_vec3(unit.lights.at(0).p1)) << d.x;
  }
  const std::string far = R"({"nbounces": 4, "rendermode": "pathtracer",
    "camera": {"type": "pinhole", "width": 16, "height": 12, "position": [0, 1, -5], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"backgroundcolor": [0, 0, 0],
      "lightsources": [{"type": "directional", "direction": [0, -1, 0.2], "intensity": [2, 2, 2]}],
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "dielectric"}},
                 {"type": "sphere", "center": [1e30, 0, 0], "radius": 1e28, "material": {"type": "diffuse"}}]}})";
  // A scene 1e30 across is beyond the coordinate limit: refused by the key.
  // One within it whose directional light is bright enough that E pi R^2
  // overflows: refused by the light, both before any kernel is built.
  std::string bright = far;
  bright.replace(bright.find("[1e30, 0, 0], \"radius\": 1e28"), std::string("[1e30, 0, 0], \"radius\": 1e28").size(),
                 "[1e11, 0, 0], \"radius\": 1e10");
  bright.replace(bright.find("[2, 2, 2]"), std::string("[2, 2, 2]").size(), "[1e20, 1e20, 1e20]");
  const std::pair<std::string, std::vector<std::string>> cases[] = {
      {write_scene("dir_far.json", far), {"dir_far.json: /scene/shapes/1/center/0", "coordinate limit", "scale the scene"}},
      {write_scene("dir_bright.json", bright),
       {"dir_bright.json: /scene/lightsources/0: its power", "overflows a 32-bit float", "scale the scene"}}};
  for (const auto& [scene, expected] : cases)
    for (const char* caustics : {"on", "off"}) {
      const test::CliResult r = test::run_cli("render " + scene + " --caustics " + std::string(caustics) +
                                              " --spp 1 -q --device " + test::device_spec() + " -o " +
                                              test::temp_dir() + "/far.pfm");
      EXPECT_EQ(r.status, 1) << r.output;
      for (const std::string& part : expected) EXPECT_TRUE(test::Contains(r.output, {part})) << r.output;
      EXPECT_EQ(r.output.find("kernel"), std::string::npos) << r.output;
    }
  // The same for a sky whose power overflows, in phong's photon pass too
  // (it failed with "shade_surface_phong declares 48 arguments, the host
  // binds 44").
  write_image(test::temp_dir() + "/huge_sky.pfm", ImageF(8, 4, 3e38f), DisplaySettings{});
  const std::string sky = write_scene("sky_huge.json", R"({"nbounces": 4, "rendermode": "phong",
    "camera": {"type": "pinhole", "width": 16, "height": 12, "position": [0, 1, -5], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"environment": {"file": "huge_sky.pfm"},
      "lightsources": [{"type": "pointlight", "position": [0, 3, 0], "intensity": [1, 1, 1]}],
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "dielectric"}},
                 {"type": "triangle", "v0": [-5, -1, -5], "v1": [5, -1, -5], "v2": [0, -1, 5],
                  "material": {"type": "diffuse"}}]}})");
  for (const char* mode : {"phong", "path"}) {
    const test::CliResult r = test::run_cli("render " + sky + " --mode " + mode + " --caustics on --spp 1 -q --device " +
                                            test::device_spec() + " -o " + test::temp_dir() + "/sky.pfm");
    EXPECT_EQ(r.status, 1) << mode << ": " << r.output;
    EXPECT_TRUE(test::Contains(r.output, {"sky_huge.json: the environment", "overflows a 32-bit float"}))
        << mode << ": " << r.output;
  }
}

// ----------------------------------------------- kernel functions, on the host

Light placed_light(glm::dvec3 d, glm::dvec3 e) {
  const Scene s = load_scene(write_scene("dir_one.json", floor_scene(directional(d, e), "phong", kDiffuse)));
  return whitted_lights(s).at(0);
}

TEST(DirectionalLight, NextEventEstimationArrivesAlongMinusDPastTheScene) {
  const Light l = placed_light(glm::normalize(glm::dvec3(1, -2, 0.5)), {2, 3, 4});
  const float3 d = make_float3(l.p1.x, l.p1.y, l.p1.z);
  for (const float3 p : {make_float3(0, 0, 0), make_float3(8, 0, -8), make_float3(-100, 50, 3)}) {
    LightSample s;
    ASSERT_TRUE(sample_light(&l, nullptr, 0.5f, p, make_float2(0.3f, 0.7f), &s));
    EXPECT_TRUE(s.delta);
    EXPECT_EQ(s.pdf, 0.5f);  // the pick probability alone
    EXPECT_EQ(s.wi.x, -d.x);
    EXPECT_EQ(s.wi.y, -d.y);
    EXPECT_EQ(s.wi.z, -d.z);
    EXPECT_EQ(s.radiance.x, 2.0f);
    EXPECT_EQ(s.radiance.z, 4.0f);
    // The shadow ray's target lies beyond the bounding sphere along -d.
    const float3 c = make_float3(l.p0.x, l.p0.y, l.p0.z);
    EXPECT_GT(length(s.point - c), l.p0.w);
    EXPECT_GT(s.distance, length(p - c) + l.p0.w);
    EXPECT_NEAR(length(s.point - (p + s.distance * s.wi)), 0.0f, 1e-4f * s.distance);
    EXPECT_EQ(light_pdf(&l, nullptr, 0.5f, p, s.point, s.wi), 0.0f);
  }
  EXPECT_EQ(light_intensity_toward(&l, nullptr, d).y, 3.0f);  // phong's E
}

// Every photon carries E pi R^2 (the direction is fixed, only the start
// is random), travels along d, starts outside the bounding sphere and
// crosses its disk uniformly (half of them within R / sqrt 2 of its
// centre's line).
TEST(DirectionalLight, UnguidedPhotonsCarryItsPower) {
  const Light l = placed_light(glm::normalize(glm::dvec3(1, -2, 0.5)), {2, 3, 4});
  const double r = l.p0.w;
  const glm::dvec3 c(l.p0.x, l.p0.y, l.p0.z), d(l.p1.x, l.p1.y, l.p1.z);
  const int n = 1 << 16;
  double sum = 0.0;
  int inner = 0;
  test::emit_photons(l, nullptr, n, 11, [&](float3 origin, float3 dir, float3 flux) {
    EXPECT_EQ(dir.x, l.p1.x);
    EXPECT_EQ(dir.y, l.p1.y);
    EXPECT_EQ(dir.z, l.p1.z);
    const glm::dvec3 o = glm::dvec3(origin.x, origin.y, origin.z) - c;
    EXPECT_GT(glm::length(o), r);
    EXPECT_LT(glm::dot(o, d), 0.0);  // heading in
    const double off_axis = glm::length(o - glm::dot(o, d) * d);
    EXPECT_LE(off_axis, r * 1.0001);
    inner += off_axis < r / std::sqrt(2.0);
    EXPECT_NEAR(flux.y, 3.0 * kPi * r * r, 1e-5 * 3.0 * kPi * r * r);
    sum += 0.2126 * flux.x + 0.7152 * flux.y + 0.0722 * flux.z;
  });
  EXPECT_NEAR(sum / n, light_type(LIGHT_DIRECTIONAL).power(l), 1e-5 * sum / n);
  const double half = 0.5 * n, se = std::sqrt(n * 0.25);
  EXPECT_NEAR(inner, half, 5.0 * se);
}

// -------------------------------------------------------------- renders

using Rendered = test::CameraRender;

Rendered render(const std::string& name, const std::string& scene_text, RenderMode mode, int spp = 1) {
  test::CameraRenderOptions o;
  o.spp = spp;
  o.seed = 1;
  return test::render_with_camera(write_scene(name, scene_text), mode, o);
}

glm::dvec3 floor_point(const CameraGPU& camera, double px, double py) {
  float d[3];
  camera_plane_point(&camera, float(px), float(py), d);
  const glm::dvec3 o(camera.position.x, camera.position.y, camera.position.z), dir(d[0], d[1], d[2]);
  return o + (-o.y / dir.y) * dir;
}

// Path mode: a Lambertian floor at theta from the light reflects
// (rho / pi) E cos(theta) at every pixel, exactly: next-event estimation
// toward a delta light has no variance and the background is black.
TEST(DirectionalLight, PathFloorIsRhoOverPiTimesECosine) {
  const glm::dvec3 e(2, 3, 4), rho(0.5, 0.25, 0.75);
  for (double theta : {0.0, 35.0, 80.0}) {
    const Rendered r = render("dir_path.json", floor_scene(directional(tilted(theta), e), "pathtracer", kDiffuse),
                             RenderMode::Path, int(test::sized(4, 2)));
    const double c = std::cos(theta * kPi / 180);
    for (int py = 0; py < r.image.height; ++py)
      for (int px = 0; px < r.image.width; ++px)
        for (int k = 0; k < 3; ++k) {
          const double expected = rho[k] / kPi * e[k] * c;
          ASSERT_NEAR(r.image.at(px, py)[k], expected, 2e-5 * expected)
              << theta << " degrees, pixel " << px << ", " << py << ", channel " << k;
        }
  }
  // From below (theta > 90): the floor's top is dark, in phong as well.
  for (RenderMode mode : {RenderMode::Path, RenderMode::Phong}) {
    const Rendered r = render("dir_below.json",
                              floor_scene(directional(tilted(120), e), mode == RenderMode::Path ? "pathtracer" : "phong",
                                          mode == RenderMode::Path ? kDiffuse
                                                                   : R"({"diffusecolor": [1, 1, 1], "kd": 1, "ks": 1})"),
                              mode, 2);
    for (float v : r.image.rgb) ASSERT_EQ(v, 0.0f);
  }
}

// Phong: Blinn-Phong with intensity E and no falloff,
// E (kd diffuse cos + ks specular (n . h)^exponent) with h halfway between
// the light and the eye (kernels/integrator/shade_surface_phong.cl).
TEST(DirectionalLight, PhongFloorIsBlinnPhong) {
  const glm::dvec3 e(2, 3, 4), diffuse(0.5, 0.25, 0.75), specular(1.0, 0.5, 0.25);
  const double kd = 0.8, ks = 0.6, exponent = 20.0, theta = 30.0;
  const std::string material =
      R"({"diffusecolor": [0.5, 0.25, 0.75], "specularcolor": [1, 0.5, 0.25], "kd": 0.8, "ks": 0.6, "ka": 0,
          "specularexponent": 20})";
  const Rendered r = render("dir_phong.json", floor_scene(directional(tilted(theta), e), "phong", material), RenderMode::Phong);
  const glm::dvec3 to_light = -tilted(theta), n(0, 1, 0), eye(0, 4, 0);
  double brightest = 0.0, dimmest = 1e30;
  for (int py = 0; py < r.image.height; ++py)
    for (int px = 0; px < r.image.width; ++px) {
      const glm::dvec3 p = floor_point(r.camera, px + 0.5, py + 0.5);
      const glm::dvec3 h = glm::normalize(to_light + glm::normalize(eye - p));
      const double lobe = std::pow(std::max(0.0, glm::dot(n, h)), exponent);
      for (int k = 0; k < 3; ++k) {
        const double expected = e[k] * (kd * diffuse[k] * glm::dot(n, to_light) + ks * specular[k] * lobe);
        ASSERT_NEAR(r.image.at(px, py)[k], expected, 1e-4 * expected + 1e-5) << "pixel " << px << ", " << py;
        if (k == 1) brightest = std::max(brightest, expected), dimmest = std::min(dimmest, expected);
      }
    }
  EXPECT_GT(brightest, 1.5 * dimmest);  // the highlight is in the picture
}

// A black ball between the light and the floor: floor points whose line
// toward the light meets it are 0, others the closed form (pixels near the
// shadow's edge or whose view meets the ball are not judged). Path mode
// and phong.
TEST(DirectionalLight, AnOccluderCastsASharpShadow) {
  const double theta = 60.0;  // the shadow falls beside the ball as the camera sees it
  const glm::dvec3 e(2, 2, 2), centre(0, 1, 0), d = tilted(theta);
  const double radius = 0.8, margin = 0.2;  // a pixel is ~0.25 wide on the floor
  const std::string ball = R"({"type": "sphere", "center": [0, 1, 0], "radius": 0.8,
    "material": {"type": "diffuse", "albedo": [0, 0, 0]}},)";
  for (RenderMode mode : {RenderMode::Path, RenderMode::Phong}) {
    const bool path = mode == RenderMode::Path;
    const Rendered r = render("dir_shadow.json",
                              floor_scene(directional(d, e), path ? "pathtracer" : "phong",
                                          path ? R"({"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})"
                                               : R"({"diffusecolor": [0.5, 0.5, 0.5], "kd": 1, "ks": 0, "ka": 0})",
                                          ball),
                              mode, 2);
    const double lit = (path ? 0.5 / kPi : 0.5) * 2.0 * std::cos(theta * kPi / 180);
    int dark = 0, bright = 0;
    for (int py = 0; py < r.image.height; ++py)
      for (int px = 0; px < r.image.width; ++px) {
        const glm::dvec3 p = floor_point(r.camera, px + 0.5, py + 0.5);
        auto miss_distance = [&](glm::dvec3 o, glm::dvec3 w) {  // of the line o + t w, t > 0, from the centre
          const double t = std::max(0.0, glm::dot(centre - o, w));
          return glm::length(centre - (o + t * w));
        };
        const glm::dvec3 eye(0, 4, 0);
        if (miss_distance(eye, glm::normalize(p - eye)) < radius + margin) continue;  // the ball in view
        const double to_ball = miss_distance(p, -d);
        const float v = r.image.at(px, py)[0];
        if (to_ball < radius - margin) {
          ASSERT_EQ(v, 0.0f) << "pixel " << px << ", " << py << " is in the shadow";
          ++dark;
        } else if (to_ball > radius + margin) {
          ASSERT_NEAR(v, lit, 1e-4 * lit) << "pixel " << px << ", " << py;
          ++bright;
        }
      }
    EXPECT_GT(dark, 15) << (path ? "path" : "phong");
    EXPECT_GT(bright, 500) << (path ? "path" : "phong");
  }
}

// The photon pass: a glass ball (radius 0.3, index 1.5, centre 0.5 above
// the floor) under a light tilted 30 degrees focuses what crosses it near
// the floor. Pure path tracing cannot find that light (a delta light seen
// through smooth glass), nor can phong's shadow rays: with caustics off
// the shadow is dark (on average below a tenth of the lit floor; path mode
// sees the lit floor through the glass). With the photon pass the caustic carries,
// within 0.4 of the axis's foot, 0.72 of the E pi r^2 the ball intercepts
// (ray-traced in double: two refractions with Fresnel, 0.82 in all), in
// path mode as reflected radiance (rho / pi) E_c and in phong (--caustics
// on) as its direct term counts irradiance, kd diffuse E_c; its peak is
// several times the lit floor's. The camera looks from the side away from
// the ball.
TEST(DirectionalLight, PhotonPassFindsTheCausticOfAGlassBall) {
  const double rho = 0.5, e = 2.0, r = 0.3, theta = 30.0;
  const glm::dvec3 d = tilted(theta), foot(0.5 * std::tan(theta * kPi / 180), 0, 0);
  const std::string floor_material = R"("material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})";
  const std::string scene = R"({"nbounces": 6, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 32, "height": 32, "position": [2.789, 2.5, 0], "lookAt": [0.289, 0, 0],
             "upVector": [0, 1, 0], "fov": 30},
  "scene": {"backgroundcolor": [0, 0, 0], "ambientlight": [0, 0, 0],
    "lightsources": [)" + directional(d, glm::dvec3(e)) + R"(],
    "shapes": [
      {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.3,
       "material": {"isrefractive": true, "refractiveindex": 1.5, "kd": 0, "ks": 0}},
      {"type": "triangle", "v0": [-3, 0, -3], "v1": [3, 0, 3], "v2": [3, 0, -3], )" + floor_material + R"(},
      {"type": "triangle", "v0": [-3, 0, -3], "v1": [-3, 0, 3], "v2": [3, 0, 3], )" + floor_material + "}]}}";
  const std::string path = write_scene("dir_caustic.json", scene);
  for (RenderMode mode : {RenderMode::Path, RenderMode::Phong}) {
    const bool path_mode = mode == RenderMode::Path;
    const int spp = int(path_mode ? test::sized(16, 4) : test::sized(8, 2));  // phong: photon passes
    test::CameraRenderOptions on, off;
    on.spp = off.spp = spp;
    on.caustics = CausticsMode::On;
    off.caustics = CausticsMode::Off;
    const test::CameraRender with = test::render_with_camera(path, mode, on),
                             without = test::render_with_camera(path, mode, off);
    // What the floor shows per unit irradiance.
    const double reflects = path_mode ? rho / kPi : rho;
    const double lit = reflects * e * std::cos(theta * kPi / 180);
    double flux = 0.0, peak = 0.0, shadow_sum = 0.0;
    int shadowed = 0;
    for (int py = 0; py < with.image.height; ++py)
      for (int px = 0; px < with.image.width; ++px) {
        const glm::dvec3 p = floor_point(with.camera, px + 0.5, py + 0.5);
        // The floor area the pixel covers (a parallelogram of its corners).
        const glm::dvec3 p00 = floor_point(with.camera, px, py), p10 = floor_point(with.camera, px + 1, py),
                         p01 = floor_point(with.camera, px, py + 1);
        const double area = glm::length(glm::cross(p10 - p00, p01 - p00));
        const double on_value = with.image.at(px, py)[1], off_value = without.image.at(px, py)[1];
        // Well inside the ball's shadow (the line toward the light passes
        // the centre within r - 0.05).
        const glm::dvec3 centre(0, 0.5, 0);
        const double t = glm::dot(centre - p, -d);
        if (glm::length(centre - (p - t * d)) < r - 0.05) {
          shadow_sum += off_value;
          ++shadowed;
        }
        if (glm::length(p - foot) < 0.4) {
          flux += (on_value - off_value) / reflects * area;
          peak = std::max(peak, on_value);
        }
      }
    const double intercepted = e * kPi * r * r;
    std::printf("[measure] %s: caustic flux %.4f of the ball's %.4f (%.3f); peak %.4f, lit floor %.4f; %d shadowed pixels\n",
                path_mode ? "path" : "phong", flux, intercepted, flux / intercepted, peak, lit, shadowed);
    EXPECT_GT(shadowed, 10);
    EXPECT_LT(shadow_sum / shadowed, 0.1 * lit) << (path_mode ? "path" : "phong") << ": the shadow without photons";
    EXPECT_NEAR(flux / intercepted, 0.72, 0.12) << (path_mode ? "path" : "phong");
    EXPECT_GT(peak, 2.0 * lit) << (path_mode ? "path" : "phong");
  }
}

}  // namespace
}  // namespace caustica
