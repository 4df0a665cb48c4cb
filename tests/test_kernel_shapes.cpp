// Path mode's two execution shapes give the same image (issue 39): the
// wavefront (kernels over queues) and the CPU shape (trace_paths.cl and
// trace_photons.cl: whole camera and photon paths per work-item) call the
// same stage functions on the same samples and photons,
// and the film sums in fixed point, so every committed path-mode scene,
// with the photon pass on and off and adaptive sampling on,
// must come out bit for bit the same, with the same per-pixel sample
// counts, the same film counters and the same ray counts.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/error.h"
#include "host/render/renderer.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

namespace fs = std::filesystem;

struct ShapeRender {
  ImageF image;
  std::vector<uint32_t> spp;
  FilmCounts counts;
  RenderStats stats;
};

ShapeRender render_with(const std::string& scene, KernelShape shape, CausticsMode caustics,
                        RenderMode mode = RenderMode::Path) {
  SessionOptions o;
  o.scene_path = scene;
  o.mode = mode;
  o.device = test::device_spec();
  o.width = int(test::sized(40, 8));
  o.spp = int(test::sized(12, 2));
  // Oclgrind interprets every work-item: a few hundred photons a map there.
  if (test::on_simulator()) o.photons = 256;
  o.seed = 7;
  o.caustics = caustics;
  o.kernel_shape = shape;
  auto session = prepare_session(o);
  EXPECT_EQ(session->settings.kernel_shape, shape);
  ShapeRender r;
  r.image = session->renderer->render(&r.stats);
  r.spp = session->renderer->film().pixel_spp();
  r.counts = session->renderer->film().counts();
  return r;
}

// The committed scenes written for path mode (the phong and binary ones
// add no path-mode feature these lack; each feature set costs the suite a
// cold build of both shapes' kernels).
TEST(KernelShapes, EveryCommittedSceneGivesTheSameBitsInBothShapes) {
  size_t compared = 0;
  for (const std::string& scene : test::committed_path_scenes()) {
    for (CausticsMode caustics : {CausticsMode::Off, CausticsMode::On}) {
      const std::string what =
          fs::path(scene).filename().string() + (caustics == CausticsMode::On ? ", photon pass on" : ", photon pass off");
      SCOPED_TRACE(what);
      ShapeRender wavefront, paths;
      try {
        wavefront = render_with(scene, KernelShape::Wavefront, caustics);
      } catch (const Error& e) {
        // Scenes that name ../shared's models (sponza_sky, armadillo) where
        // it is absent; any other refusal is a failure.
        const std::string message = e.what();
        if (message.find("mesh") != std::string::npos && test::shared_dir().empty()) continue;
        ADD_FAILURE() << message;
        continue;
      }
      paths = render_with(scene, KernelShape::Paths, caustics);
      ASSERT_EQ(wavefront.image.rgb.size(), paths.image.rgb.size());
      EXPECT_EQ(0, std::memcmp(wavefront.image.rgb.data(), paths.image.rgb.data(),
                               wavefront.image.rgb.size() * sizeof(float)))
          << "the two shapes' images differ";
      EXPECT_EQ(wavefront.spp, paths.spp);
      EXPECT_EQ(wavefront.counts.nonfinite, paths.counts.nonfinite);
      EXPECT_EQ(wavefront.counts.clamped, paths.counts.clamped);
      EXPECT_EQ(wavefront.counts.underflow, paths.counts.underflow);
      EXPECT_EQ(wavefront.stats.secondary_rays, paths.stats.secondary_rays);
      EXPECT_EQ(wavefront.stats.shadow_rays, paths.stats.shadow_rays);
      EXPECT_EQ(wavefront.stats.photon_maps, paths.stats.photon_maps);
      EXPECT_EQ(wavefront.stats.photon_rays, paths.stats.photon_rays);
      ++compared;
    }
  }
  EXPECT_GE(compared, 10u);
}

// One scene with everything the paths shape runs (camera paths, shadow
// rays, the photon map traced as paths, visible points and inline gathers,
// adaptive waves): small enough for Oclgrind's checks in CI.
TEST(KernelShapes, TheCausticsSceneGivesTheSameBitsInBothShapes) {
  const std::string scene = test::source_dir() + "/scenes/caustics.json";
  const ShapeRender wavefront = render_with(scene, KernelShape::Wavefront, CausticsMode::On);
  const ShapeRender paths = render_with(scene, KernelShape::Paths, CausticsMode::On);
  EXPECT_GT(paths.stats.photon_maps, 0u);
  EXPECT_EQ(wavefront.stats.photon_rays, paths.stats.photon_rays);
  EXPECT_EQ(wavefront.stats.shadow_rays, paths.stats.shadow_rays);
  EXPECT_EQ(wavefront.spp, paths.spp);
  ASSERT_EQ(wavefront.image.rgb.size(), paths.image.rgb.size());
  EXPECT_EQ(0, std::memcmp(wavefront.image.rgb.data(), paths.image.rgb.data(),
                           wavefront.image.rgb.size() * sizeof(float)));
}

// Phong's photon pass runs in the same two shapes (trace_photons.cl): the
// same photon maps, so the same image, pass after pass.
TEST(KernelShapes, PhongsPhotonPassGivesTheSameBitsInBothShapes) {
  for (const char* name : {"caustics.json", "sun_and_sky.json"}) {
    SCOPED_TRACE(name);
    const std::string scene = test::source_dir() + "/scenes/" + name;
    const ShapeRender wavefront = render_with(scene, KernelShape::Wavefront, CausticsMode::On, RenderMode::Phong);
    const ShapeRender paths = render_with(scene, KernelShape::Paths, CausticsMode::On, RenderMode::Phong);
    EXPECT_GT(paths.stats.photon_rays, 0u);
    EXPECT_EQ(wavefront.stats.photon_rays, paths.stats.photon_rays);
    ASSERT_EQ(wavefront.image.rgb.size(), paths.image.rgb.size());
    EXPECT_EQ(0, std::memcmp(wavefront.image.rgb.data(), paths.image.rgb.data(),
                             wavefront.image.rgb.size() * sizeof(float)));
  }
}

// The shape is the device's choice unless asked: paths on a CPU device.
TEST(KernelShapes, AutoPicksPathsOnACpuAndTheWavefrontElsewhere) {
  SessionOptions o;
  o.scene_path = test::source_dir() + "/scenes/cornell_box.json";
  o.device = test::device_spec();
  o.width = 8;
  o.spp = 1;
  auto session = prepare_session(o);
  EXPECT_EQ(session->settings.kernel_shape,
            session->runtime->device_info().type == "cpu" ? KernelShape::Paths : KernelShape::Wavefront);
  EXPECT_EQ(parse_kernel_shape("paths"), KernelShape::Paths);
  EXPECT_TRUE(test::Contains(test::error_of([] { parse_kernel_shape("megakernel"); }),
                             {"--kernel-shape", "auto, wavefront or paths", "megakernel"}));
}

}  // namespace
}  // namespace caustica
