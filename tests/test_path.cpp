// The path tracer end to end, on scenes whose answer is known:
// - furnace: a Lambertian sphere of albedo rho under a uniform background of
//   radiance 1 is rho everywhere on it and 1 elsewhere;
// - a point light of intensity pi at the centre of a closed Lambertian
//   sphere of radius 1 and albedo 0.5 gives radiance 1 on the whole inner
//   surface (0.5 direct, doubled by the interreflections: 0.5 / (1 - 0.5));
// - light sampling alone, BSDF sampling alone and their MIS combination
//   agree on an area-lit scene within their standard errors, and on a floor
//   under a triangle light seen at grazing angles (shadow rays aimed from
//   their offset origins);
// - the same seed gives the same bits for any work-group size and for one
//   or two PoCL threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "host/app/session.h"
#include "host/render/renderer.h"
#include "tests/support/path_render.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::PathRender;
using test::write_scene;

PathRender render(const std::string& scene, int spp, uint32_t strategy = PATH_STRATEGY_MIS, size_t local = 64) {
  test::PathRenderOptions o;
  o.strategy = strategy;
  o.local_size = local;
  return test::render_path(scene, spp, o);
}

const char* kFurnace = R"({"nbounces": 8, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 48, "height": 48, "position": [0, 0, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [1, 1, 1],
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                "material": {"type": "diffuse", "albedo": [0.5, 0.25, 0.75]}}]}})";

// --check-numerics on the furnace: cosine-sampled Lambert weighs every
// sample by its albedo exactly, so bounce 1's mean weight (largest channel)
// is 0.75 and none exceeds 1; nothing non-finite, nothing dropped.
TEST(PathTracer, CheckNumericsReportsTheBsdfWeightsPerBounce) {
  const std::string scene = write_scene("furnace.json", kFurnace);
  const test::CliResult r = test::run_cli("render " + scene + " --spp 4 --check-numerics --device " +
                                          test::device_spec() + " -o " + test::temp_dir() + "/f.pfm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(test::Contains(r.output, {"numerics: 0 NaN/Inf and 0 negative contributions dropped, 0 clamped",
                                        "numerics: 0 non-finite BSDF weights", "mean weight 0.7500, 0.000% above 1"}))
      << r.output;
  EXPECT_EQ(r.output.find("energy gain"), std::string::npos) << r.output;
}

TEST(PathTracer, FurnaceSphereReflectsItsAlbedo) {
  // Every path leaves the convex sphere after one bounce weighted by the
  // albedo exactly, so one sample a pixel on Oclgrind checks the same.
  const PathRender r = render(write_scene("furnace.json", kFurnace), int(test::sized(16, 1)));
  EXPECT_EQ(r.stats.film.changed(), 0u);
  const float albedo[3] = {0.5f, 0.25f, 0.75f};
  int on = 0, off = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const float* p = r.image.at(x, y);
      // Pixels well inside or well outside the sphere's disc (radius ~ 14.5
      // pixels at this fov and distance); the rim mixes both.
      const double dx = x + 0.5 - 24.0, dy = y + 0.5 - 24.0, d = std::sqrt(dx * dx + dy * dy);
      if (d < 12.0) {
        ++on;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], albedo[c], 0.01 * albedo[c]) << x << "," << y;
      } else if (d > 17.0) {
        ++off;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], 1.0f, 1e-6f) << x << "," << y;
      }
    }
  EXPECT_GT(on, 300);
  EXPECT_GT(off, 500);
}

const char* kClosedSphere = R"({"nbounces": 1000, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 32, "height": 32, "position": [0, 0, -0.5], "lookAt": [0, 0.2, 1],
             "upVector": [0, 1, 0], "fov": 60},
  "scene": {"backgroundcolor": [0, 0, 0],
    "lightsources": [{"type": "pointlight", "position": [0, 0, 0], "intensity": [3.14159265, 3.14159265, 3.14159265]}],
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}]}})";

TEST(PathTracer, PointLightInAClosedSphereGivesRadianceOne) {
  // 16 spp on Oclgrind: the per-pixel sd (0.051 measured at 64 spp) grows
  // by sqrt(64 / spp), its bound with it; the mean's standard error there,
  // ~0.10 / 32 pixels, leaves the 0.01 tolerance at 3 of them.
  const int spp = int(test::sized(64, 16));
  const PathRender r = render(write_scene("closed.json", kClosedSphere), spp);
  EXPECT_EQ(r.stats.film.changed(), 0u);
  double sum = 0.0, sum2 = 0.0;
  const size_t n = r.image.pixel_count();
  for (size_t i = 0; i < n; ++i) {
    const double v = r.image.rgb[3 * i];
    sum += v;
    sum2 += v * v;
    EXPECT_FLOAT_EQ(r.image.rgb[3 * i], r.image.rgb[3 * i + 1]);
  }
  const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  std::printf("[measure] closed sphere: mean %.5f, per-pixel sd %.4f at %d spp\n", mean, sd, spp);
  EXPECT_NEAR(mean, 1.0, 0.01);
  EXPECT_LT(sd, 0.1 * std::sqrt(64.0 / spp));
}

// A Lambertian floor and a glossy sphere under every kind of area light: a
// rectangle light, a sphere light, an emissive cylinder, a one-sided
// emissive triangle (facing down: v0, v1, v2 clockwise seen from above) and
// a two-sided one. NEE alone, BSDF sampling alone and MIS estimate one image.
const char* kAreaLit = R"({"nbounces": 3, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 32, "height": 24, "position": [0, 2, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 50},
  "scene": {"backgroundcolor": [0.05, 0.05, 0.05],
    "lightsources": [{"type": "arealight", "position": [0, 1.5, 0], "u": [1.2, 0, 0], "v": [0, 0, -1.2],
                      "intensity": [4, 4, 4]},
                     {"type": "spherelight", "position": [1.5, 0.8, 1], "radius": 0.3, "intensity": [3, 2, 1]}],
    "shapes": [
      {"type": "triangle", "v0": [-4, 0, -4], "v1": [-4, 0, 4], "v2": [4, 0, 4],
       "material": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
      {"type": "triangle", "v0": [-4, 0, -4], "v1": [4, 0, 4], "v2": [4, 0, -4],
       "material": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
      {"type": "sphere", "center": [-0.6, 0.5, 0.2], "radius": 0.5,
       "material": {"diffusecolor": [0.8, 0.3, 0.2], "kd": 0.9, "ks": 0.1, "specularexponent": 40}},
      {"type": "cylinder", "center": [-1.6, 0.6, 1.2], "axis": [0, 1, 0], "radius": 0.1, "height": 0.3,
       "material": {"type": "emissive", "color": [1, 2, 3], "intensity": 1.5}},
      {"type": "triangle", "v0": [0.8, 1.2, -0.6], "v1": [1.6, 1.2, -0.6], "v2": [1.6, 1.2, 0.2],
       "material": {"emission": [2, 1, 0.5], "kd": 0}},
      {"type": "triangle", "v0": [-1.0, 1.0, 1.0], "v1": [-1.0, 1.0, 1.6], "v2": [-0.4, 1.0, 1.6],
       "material": {"emission": [0.5, 1, 2], "kd": 0, "twosided": true}}]}})";

// Image mean (red + green) and its standard error for MIS, light sampling
// alone and BSDF sampling alone, in that order. Per pixel, the mean of all
// passes M and of the second half B differ by E[(M - B)^2] = Var(M)
// (independent halves), so SE^2 = sum (M - B)^2 / pixels^2.
struct StrategyMeans {
  double mean[3] = {0, 0, 0}, se[3] = {0, 0, 0};
};

StrategyMeans strategy_means(const std::string& scene, int spp) {
  StrategyMeans m;
  const uint32_t strategies[3] = {PATH_STRATEGY_MIS, PATH_STRATEGY_NEE, PATH_STRATEGY_BSDF};
  for (int k = 0; k < 3; ++k) {
    const PathRender r = render(scene, spp, strategies[k]);
    EXPECT_EQ(r.stats.film.changed(), 0u);
    double sum = 0.0, var = 0.0;
    const size_t n = r.image.pixel_count();
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c) {
        sum += r.image.rgb[3 * i + c];
        const double d = r.image.rgb[3 * i + c] - r.half.rgb[3 * i + c];
        var += d * d;
      }
    m.mean[k] = sum / n;
    m.se[k] = std::sqrt(var) / n;
  }
  return m;
}

TEST(PathTracer, LightSamplingBsdfSamplingAndMisAgree) {
  // 16 spp on Oclgrind: the bounds are in the measured standard errors.
  const StrategyMeans m = strategy_means(write_scene("arealit.json", kAreaLit), int(test::sized(256, 16)));
  const double* mean = m.mean;
  const double* se = m.se;
  std::printf("[measure] area-lit mean (r+g): MIS %.5f +- %.5f, NEE %.5f +- %.5f, BSDF %.5f +- %.5f\n", mean[0],
              se[0], mean[1], se[1], mean[2], se[2]);
  EXPECT_NEAR(mean[1], mean[0], 4.0 * std::hypot(se[0], se[1]));
  EXPECT_NEAR(mean[2], mean[0], 4.0 * std::hypot(se[0], se[2]));
  // MIS is never much noisier than either technique alone.
  EXPECT_LT(se[0], 1.2 * std::min(se[1], se[2]));
}

// Regression (issue 14): a floor lit by a one-sided triangle light 1.2
// above it, seen from the floor at cosines down to ~0.2. Shadow rays start
// off the floor by its error bound (~3e-5 up); aimed along the direction
// from the unoffset point, they crossed the light's plane 1.4e-4 before the
// sampled point and the light shadowed itself: light sampling lost 3.6%
// (14 standard errors) against BSDF sampling. spawn_ray_to (geometry.h)
// aims from the offset origin.
const char* kCeilingLight = R"({"nbounces": 3, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 32, "height": 24, "position": [0, 2, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 50},
  "scene": {"backgroundcolor": [0.05, 0.05, 0.05],
    "shapes": [
      {"type": "triangle", "v0": [-4, 0, -4], "v1": [-4, 0, 4], "v2": [4, 0, 4],
       "material": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
      {"type": "triangle", "v0": [-4, 0, -4], "v1": [4, 0, 4], "v2": [4, 0, -4],
       "material": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
      {"type": "triangle", "v0": [0.8, 1.2, -0.6], "v1": [1.6, 1.2, -0.6], "v2": [1.6, 1.2, 0.2],
       "material": {"emission": [2, 1, 0.5], "kd": 0}}]}})";

TEST(PathTracer, ShadowRaysReachTheLightTheySampled) {
  const StrategyMeans m = strategy_means(write_scene("ceiling.json", kCeilingLight), int(test::sized(128, 16)));
  std::printf("[measure] ceiling-light mean (r+g): NEE %.5f +- %.5f, BSDF %.5f +- %.5f\n", m.mean[1], m.se[1],
              m.mean[2], m.se[2]);
  EXPECT_NEAR(m.mean[1], m.mean[2], 4.0 * std::hypot(m.se[1], m.se[2]));
  // The bias was 3.6% of the image; noise alone allows far less here. Not
  // at Oclgrind's 16 spp, where 4 standard errors are ~3.7% of the mean:
  // there the render checks the kernels' memory behaviour and the 4-sigma
  // agreement above only.
  if (!test::on_simulator()) EXPECT_NEAR(m.mean[1], m.mean[2], 0.01 * m.mean[2]);
}

// The CLI's .pfm output for one or two PoCL threads, and renders with two
// work-group sizes: the same bits.
TEST(PathTracer, SameBitsForAnyThreadCountAndWorkGroupSize) {
  const std::string scene = write_scene("arealit.json", kAreaLit);
  const std::string dir = test::temp_dir();
  std::string outputs[2];
  for (int k = 0; k < 2; ++k) {
    const std::string out = dir + "/out" + std::to_string(k) + ".pfm";
    const std::string cmd = "POCL_MAX_PTHREAD_COUNT=" + std::to_string(k + 1) + " " + test::binary_path() +
                            " render " + scene + " --mode path --spp 8 --device " + test::device_spec() + " -q -o " +
                            out;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(out, std::ios::binary);
    outputs[k].assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  ASSERT_FALSE(outputs[0].empty());
  EXPECT_EQ(outputs[0], outputs[1]);
  const PathRender a = render(scene, 8, PATH_STRATEGY_MIS, 16), b = render(scene, 8, PATH_STRATEGY_MIS, 64);
  ASSERT_EQ(a.image.rgb.size(), b.image.rgb.size());
  EXPECT_EQ(0, std::memcmp(a.image.rgb.data(), b.image.rgb.data(), a.image.rgb.size() * sizeof(float)));
}

// Path regeneration: with 64 path slots for 32 x 24 pixels x 8 passes, all
// but the first 64 samples start in the slot of a path that ended, in an
// order the scheduling decides; the image is the same bits as with slots to
// spare, and the same bits for a work-group size that takes samples and
// queue slots in other groups. Paths per pixel and rays add up exactly.
TEST(PathTracer, RegeneratedPathsGiveTheSameBitsAsSlotsToSpare) {
  const std::string scene = write_scene("arealit.json", kAreaLit);
  // On the simulator (Oclgrind, a CI step) a quarter of the image and of
  // the slots, half the samples: 768 paths through 16 slots.
  const int spp = int(test::sized(8, 4)), width = int(test::sized(32, 16)), height = int(test::sized(24, 12));
  test::PathRenderOptions wavefront, few, few_wide;
  wavefront.kernel_shape = few.kernel_shape = few_wide.kernel_shape = KernelShape::Wavefront;  // the queues' test
  for (test::PathRenderOptions* o : {&wavefront, &few, &few_wide}) {
    o->width = width;
    o->height = height;
  }
  const size_t slots = test::sized(64, 16);
  few.path_slots = slots;
  few_wide.path_slots = slots;
  few_wide.local_size = 16;
  const PathRender spare = render_path(scene, spp, wavefront), a = render_path(scene, spp, few),
                   b = render_path(scene, spp, few_wide);
  for (const PathRender* r : {&a, &b}) {
    ASSERT_EQ(r->image.rgb.size(), spare.image.rgb.size());
    EXPECT_EQ(0, std::memcmp(r->image.rgb.data(), spare.image.rgb.data(), spare.image.rgb.size() * sizeof(float)));
    EXPECT_EQ(r->stats.camera_rays, spare.stats.camera_rays);
    EXPECT_EQ(r->stats.secondary_rays, spare.stats.secondary_rays);
    EXPECT_EQ(r->stats.shadow_rays, spare.stats.shadow_rays);
    EXPECT_EQ(r->stats.blocking_transfers, 0u);
  }
  EXPECT_EQ(spare.stats.camera_rays, uint64_t(width * height * spp));
  // Many more iterations (each a count read) through few slots than through
  // the slots the image gets by default (every path at once).
  std::printf("[measure] count reads: %llu through %zu slots, %llu with slots to spare\n",
              (unsigned long long)a.stats.count_reads, slots, (unsigned long long)spare.stats.count_reads);
  EXPECT_GT(a.stats.count_reads, 4 * spare.stats.count_reads);
}

}  // namespace
}  // namespace caustica
