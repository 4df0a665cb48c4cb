// Photon-mapped caustics (issue 13) end to end on scenes/caustics.json at
// 64 x 48, against tests/references/caustics_pt_64x48.pfm: path tracing
// alone (--caustics off) at 131072 samples per pixel, seed 4242, made by
//   caustica render scenes/caustics.json --width 64 --height 48 \
//     --caustics off --spp 131072 --seed 4242 -o caustics_pt_64x48.pfm
// (about 8 minutes on 2 cores). Caustic region: the glass sphere's focus on
// the floor (x 36-46, y 32-34) and the mirror's patch on the back wall
// (x 10-20, y 10-21; a soft one: a flat mirror's image of the light), pixel
// boxes picked from the reference, clear of the light's highlights on the
// glass (sub-pixel, so their error is pixel sampling, the same for both).
// - the photon-mapped image converges to the reference in the caustic
//   region: relMSE falls with a log-log slope near -2/3 (SPPM's rate with
//   alpha = 2/3) and still falls at the end (no plateau from a fixed radius);
// - the light in the caustic region and in the whole image matches the
//   reference within its noise: nothing counted twice, nothing lost;
// - at equal cost (rays traced, photon paths included) the caustic region's
//   error is at least 3x below path tracing alone.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "host/render/film.h"
#include "tests/support/pixel_boxes.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

const std::vector<test::PixelBox> kCausticRegion = {{36, 46, 32, 34}, {10, 20, 10, 21}};

double region_rel_mse(const ImageF& img, const ImageF& ref) { return test::boxes_rel_mse(img, ref, kCausticRegion); }
double region_sum(const ImageF& img) { return test::boxes_sum(img, kCausticRegion); }
using test::image_sum;

const ImageF& reference() {
  static const ImageF ref = read_pfm(test::source_dir() + "/tests/references/caustics_pt_64x48.pfm");
  return ref;
}

struct CausticsRun {
  std::vector<int> spp;
  std::vector<double> region_error;
  ImageF image;
  uint64_t rays = 0;
};

CausticsRun render(CausticsMode caustics, int spp, uint32_t photons, uint32_t seed) {
  SessionOptions o;
  o.scene_path = test::source_dir() + "/scenes/caustics.json";
  o.device = test::device_spec();
  o.width = 64;
  o.height = 48;
  o.spp = spp;
  o.seed = seed;
  o.caustics = caustics;
  o.photons = photons;
  // The photon pass's convergence and its lead over path tracing are
  // claims about the two estimators: uniform sampling for both.
  o.adaptive = false;
  auto s = prepare_session(o);
  EXPECT_EQ(s->features.caustics, caustics == CausticsMode::On);
  CausticsRun run;
  RenderStats stats;
  run.image = s->renderer->render(&stats, {}, [&](const Film& film, double) {
    const int n = film.passes();
    if ((n & (n - 1)) == 0 && n >= 4) {
      run.spp.push_back(n);
      run.region_error.push_back(region_rel_mse(film.mean(), reference()));
    }
    return true;
  });
  run.rays = stats.rays();
  EXPECT_EQ(stats.film.changed(), 0u);
  return run;
}

void check_convergence(const CausticsRun& r) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t k = 0; k < r.spp.size(); ++k) {
    std::printf("[measure] caustics.json photon pass, %d passes: caustic-region relMSE %.4g\n", r.spp[k],
                r.region_error[k]);
    if (r.spp[k] < 8) continue;
    const double x = std::log(double(r.spp[k])), y = std::log(r.region_error[k]);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::printf("[measure] log-log slope of the caustic region's relMSE against passes (8..256): %.3f\n", slope);
  EXPECT_LT(slope, -0.5);
  EXPECT_GT(slope, -1.0);
  // Still falling at the end: no plateau from a radius that stopped shrinking.
  EXPECT_LT(r.region_error.back(), 0.8 * r.region_error[r.region_error.size() - 3]);
}

void check_light_matches(const CausticsRun& r) {
  const double region = region_sum(r.image), region_ref = region_sum(reference());
  const double all = image_sum(r.image), all_ref = image_sum(reference());
  std::printf("[measure] caustic region: photon pass %.4f, reference %.4f (ratio %.4f); whole image %.4f vs %.4f "
              "(ratio %.4f)\n", region, region_ref, region / region_ref, all, all_ref, all / all_ref);
  // Counting the caustic twice would double its excess over the direct
  // light; leaving it out would remove it. Both far beyond these bounds.
  EXPECT_NEAR(region / region_ref, 1.0, 0.05);
  EXPECT_NEAR(all / all_ref, 1.0, 0.02);
}

void check_beats_path_tracing(const CausticsRun& photons) {
  // Path tracing alone with the same number of rays (about: its passes cost
  // fewer rays each, so it gets more of them).
  const CausticsRun probe = render(CausticsMode::Off, 16, 0, 1);
  const int spp = int(16.0 * double(photons.rays) / double(probe.rays));
  const CausticsRun alone = render(CausticsMode::Off, spp, 0, 1);
  const double pt = region_rel_mse(alone.image, reference()), pm = photons.region_error.back();
  std::printf("[measure] equal rays (%llu vs %llu): path tracing alone %d spp, caustic-region relMSE %.4g; with "
              "the photon pass 256 passes, %.4g (%.1fx lower)\n",
              (unsigned long long)alone.rays, (unsigned long long)photons.rays, spp, pt, pm, pt / pm);
  EXPECT_GT(pt / pm, 3.0);
}

// One photon-mapped render serves the three checks (a test is a process of
// its own under ctest).
TEST(Caustics, PhotonMapConvergesToThePathTracedReferenceWithoutDoubleCounting) {
  const CausticsRun run = render(CausticsMode::On, 256, 1u << 15, 1);
  {
    SCOPED_TRACE("convergence");
    check_convergence(run);
  }
  {
    SCOPED_TRACE("light in the caustic region and the image");
    check_light_matches(run);
  }
  {
    SCOPED_TRACE("equal cost against path tracing alone");
    check_beats_path_tracing(run);
  }
}

}  // namespace
}  // namespace caustica
