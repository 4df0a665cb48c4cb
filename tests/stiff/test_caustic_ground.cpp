// The photon pass on the stiff case of issue 19: scenes/stiff_ground.json,
// a ground sphere of radius 1000 under small glass, mirror and diffuse
// spheres, a small area light (0.08 across, 1.6 up) and a dim sky; the
// scene box is thousands of times the objects, which made the old
// scene-box radius cover whole objects. At 72 x 48 against
// tests/references/stiff_ground_pt_72x48.pfm: path tracing alone at 262144
// samples per pixel, seed 4242, made by
//   caustica render scenes/stiff_ground.json --width 72 --height 48 \
//     --caustics off --spp 262144 --seed 4242 --no-error-estimate \
//     -o stiff_ground_pt_72x48.pfm
// (about 9 minutes on 2 cores). Caustic region: the glass sphere's focus
// on the ground (a pixel box picked from the reference). Checked:
// - `auto` keeps the pass here (the caustic is 5% of the image's light);
// - at equal rays traced (photon rays included) the caustic region's
//   relMSE is at least 3x below path tracing alone's, both as means over
//   seeds (32 for path tracing alone, whose error here is heavy-tailed:
//   most seeds give 0.2-0.5, a few fireflies 1-10; 8 for the photon pass);
// - the light in the caustic region and in the whole image matches the
//   reference within its noise: nothing missing, nothing counted twice.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/app/session.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "tests/support/pixel_boxes.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

const std::vector<test::PixelBox> kCausticRegion = {{33, 39, 30, 32}};

const ImageF& reference() {
  static const ImageF ref = read_pfm(test::source_dir() + "/tests/references/stiff_ground_pt_72x48.pfm");
  return ref;
}

double region_rel_mse(const ImageF& img) { return test::boxes_rel_mse(img, reference(), kCausticRegion); }
double region_sum(const ImageF& img) { return test::boxes_sum(img, kCausticRegion); }
using test::image_sum;

struct GroundRender {
  ImageF image;
  uint64_t rays = 0;
  std::string decision;
  bool caustics = false;
};

GroundRender render(CausticsMode caustics, int spp, uint32_t seed) {
  SessionOptions o;
  o.scene_path = test::source_dir() + "/scenes/stiff_ground.json";
  o.device = test::device_spec();
  o.width = 72;
  o.height = 48;
  o.spp = spp;
  o.seed = seed;
  o.caustics = caustics;
  // Issue 19's claim compares the two estimators under uniform sampling
  // (adaptive sampling, which concentrates path tracing's samples on the
  // caustic, narrows the gap).
  o.adaptive = false;
  auto s = prepare_session(o);
  GroundRender run;
  run.caustics = s->features.caustics;
  RenderStats stats;
  run.image = s->renderer->render(&stats);
  test::expect_finite_render(run.image, stats.film, "stiff_ground.json");
  run.rays = stats.rays();
  run.decision = stats.caustics_decision;
  return run;
}

TEST(CausticGround, AutoKeepsThePassBeatsPathTracingThreefoldAndKeepsTheLight) {
  const int spp = int(test::sized(256, 8));
  const GroundRender photons = render(CausticsMode::Auto, spp, 1);
  std::printf("[measure] auto: %s\n", photons.decision.c_str());
  ASSERT_TRUE(photons.caustics);
  EXPECT_EQ(photons.decision.find("off after"), std::string::npos) << photons.decision;
  // On Oclgrind (8 passes) the second map, which judges the light, has not come yet.
  if (test::on_simulator()) return;  // the statistics below need the full counts
  EXPECT_NE(photons.decision.find("kept"), std::string::npos) << photons.decision;

  // Path tracing alone with the same number of rays (about: its passes
  // cost fewer rays each, so it gets more of them). Errors are means over
  // seeds: path tracing's error on a caustic is heavy-tailed (one seed's
  // firefly can carry most of it), so one seed decides nothing.
  const GroundRender probe = render(CausticsMode::Off, 16, 1);
  const int alone_spp = int(16.0 * double(photons.rays) / double(probe.rays));
  // 32 seeds of path tracing alone (its error is the heavy-tailed one) and 8
  // of the photon pass.
  constexpr int kAloneSeeds = 32, kPassSeeds = 8;
  double pt = 0.0, pm = 0.0;
  std::string alone_seeds, pass_seeds;
  for (uint32_t seed = 1; seed <= kAloneSeeds; ++seed) {
    const double e = region_rel_mse(render(CausticsMode::Off, alone_spp, seed).image);
    pt += e / kAloneSeeds;
    alone_seeds += " " + std::to_string(e).substr(0, 5);
  }
  for (uint32_t seed = 1; seed <= kPassSeeds; ++seed) {
    const double e =
        region_rel_mse(seed == 1 ? photons.image : render(CausticsMode::Auto, spp, seed).image);
    pm += e / kPassSeeds;
    pass_seeds += " " + std::to_string(e).substr(0, 5);
  }
  std::printf("[measure] equal rays (%llu rays a photon-pass render): caustic-region relMSE of path tracing alone "
              "(%d spp) over %d seeds:%s; with the photon pass (%d spp) over %d seeds:%s; means %.4g and %.4g (%.1fx "
              "lower)\n",
              (unsigned long long)photons.rays, alone_spp, kAloneSeeds, alone_seeds.c_str(), spp, kPassSeeds,
              pass_seeds.c_str(), pt, pm, pt / pm);
  EXPECT_GT(pt / pm, 3.0);

  const double region = region_sum(photons.image), region_ref = region_sum(reference());
  const double all = image_sum(photons.image), all_ref = image_sum(reference());
  std::printf("[measure] caustic region: photon pass %.4f, reference %.4f (ratio %.4f); whole image %.4f vs %.4f "
              "(ratio %.4f)\n",
              region, region_ref, region / region_ref, all, all_ref, all / all_ref);
  EXPECT_NEAR(region / region_ref, 1.0, 0.05);
  EXPECT_NEAR(all / all_ref, 1.0, 0.02);
}

}  // namespace
}  // namespace caustica
