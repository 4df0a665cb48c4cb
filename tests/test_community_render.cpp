// Renders every community scene in ../shared (skipped when absent) in phong
// mode at a small size: whatever loads must render without crashing and
// without the film dropping (NaN/Inf, negative) or clamping a single
// contribution; whatever does not load must fail
// with a caustica::Error naming the file (test_community_corpus.cpp pins
// which is which).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "host/app/session.h"
#include "host/error.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

TEST(CommunityCorpus, EveryLoadableSceneRendersInPhong) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const std::filesystem::path dir = std::filesystem::path(shared) / "scenes-coursework" / "community";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 30u);
  int rendered = 0;
  for (const auto& f : files) {
    SessionOptions o;
    o.scene_path = f.string();
    o.mode = RenderMode::Phong;
    o.width = 48;
    o.device = test::device_spec();
    std::unique_ptr<Session> session;
    try {
      session = prepare_session(o);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(f.filename().string()), std::string::npos) << e.what();
      std::printf("[corpus] %-80s error: %s\n", f.filename().c_str(), e.what());
      continue;
    }
    RenderStats stats;
    const ImageF image = session->renderer->render(&stats);
    // The film counts what it dropped or clamped rather than hiding it, so
    // "no NaN/Inf reached the film" is a count, not a property of the output.
    EXPECT_EQ(stats.film.changed(), 0u) << f.filename() << ": " << stats.film.nonfinite << " NaN/Inf, "
                                      << stats.film.negative << " negative, " << stats.film.clamped << " clamped";
    ++rendered;
    std::printf("[corpus] %-80s rendered %dx%d, %zu prims\n", f.filename().c_str(), image.width, image.height,
                session->scene.primitive_count());
  }
  EXPECT_GE(rendered, 20);
}

}  // namespace
}  // namespace caustica
