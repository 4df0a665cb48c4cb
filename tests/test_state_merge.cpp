// Renders of a subset of passes and `caustica merge` (issue 23;
// host/render/pass_set.h, host/render/state_merge.h): passes traced in
// pieces (contiguous halves, or interleaved blocks as MPI ranks trace them)
// and added up give the same bits as one render of all of them: the sums,
// the half buffer, the counts and the image; in process and through the
// caustica binary (render --passes, merge, resume of a merged state). What
// cannot be added is refused with one precise error: overlapping passes,
// other scenes or settings, adaptive and photon-pass states, damaged files.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/error.h"
#include "host/render/render_state.h"
#include "host/render/renderer.h"
#include "host/render/state_merge.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::Contains;

std::string cornell() { return test::source_dir() + "/scenes/cornell_box.json"; }

struct Prepared {
  std::unique_ptr<Session> session;
  RenderSettings settings;
};

Prepared prepare(const std::string& scene, int passes, bool adaptive = false, uint32_t seed = 0,
                 CausticsMode caustics = CausticsMode::Off) {
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  o.mode = RenderMode::Path;
  o.spp = passes;
  o.width = 24;
  o.caustics = caustics;
  o.adaptive = adaptive;
  o.seed = seed;
  Prepared p;
  p.session = prepare_session(o);
  p.settings = p.session->settings;
  return p;
}

// One renderer tracing `pieces` ([begin, end) each, in order) into one
// film; its state with its identity.
RenderState render_pieces(Prepared& p, const std::vector<std::pair<int, int>>& pieces, ImageF* image = nullptr) {
  Session& s = *p.session;
  Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
  r.begin();
  RenderStats stats;
  for (const auto& [begin, end] : pieces) {
    StopConditions stop;
    stop.first_pass = begin;
    stop.passes = end;
    r.run(stop, &stats);
  }
  if (image) *image = r.finish(&stats);
  RenderState state = r.state();
  state.identity = render_identity(scene_hash(s.scene), s.mode, p.settings, "spatial");
  return state;
}

void expect_same_film(const FilmState& a, const FilmState& b) {
  EXPECT_EQ(a.passes, b.passes);
  EXPECT_EQ(a.held, b.held) << a.held.describe() << " vs " << b.held.describe();
  EXPECT_EQ(a.spp, b.spp);
  EXPECT_EQ(a.half_start, b.half_start);
  EXPECT_EQ(a.counters, b.counters);
  EXPECT_EQ(a.pixel_rays, b.pixel_rays);
  ASSERT_EQ(a.accumulated.size(), b.accumulated.size());
  EXPECT_TRUE(a.accumulated == b.accumulated) << "the 128-bit sums (and half buffers) differ";
}

bool same_bits(const ImageF& a, const ImageF& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// 40 passes: the half buffer is [32, 40); the pieces cross 1, 2, 4, 8, 16
// and 32 in the middle of their ranges.
constexpr int kPasses = 40;

TEST(StateMerge, PiecesOfPassesMergeToTheBitsOfOneRender) {
  Prepared p = prepare(cornell(), kPasses);
  ASSERT_TRUE(p.settings.half_buffer);
  ImageF whole_image;
  const RenderState whole = render_pieces(p, {{0, kPasses}}, &whole_image);
  ASSERT_EQ(whole.film.held, PassSet::range(0, kPasses));
  // Contiguous halves, and one whose last pass is below the union's half.
  for (const int split : {20, 33, 31, 1}) {
    SCOPED_TRACE("split at " + std::to_string(split));
    const RenderState a = render_pieces(p, {{0, split}}), b = render_pieces(p, {{split, kPasses}});
    const RenderState merged = merge_render_states({{"b.cst", b}, {"a.cst", a}});
    expect_same_film(merged.film, whole.film);
    EXPECT_TRUE(same_bits(film_state_mean(merged.film, whole_image.width, whole_image.height), whole_image));
  }
  // Three "ranks" of interleaved blocks of 3 passes, as MPI ranks trace
  // them (host/app/mpi_render.h); the block sizes do not matter.
  std::vector<std::vector<std::pair<int, int>>> ranks(3);
  for (int first = 0, block = 0; first < kPasses; first += 3, ++block)
    ranks[block % 3].emplace_back(first, std::min(kPasses, first + 3));
  std::vector<NamedState> parts;
  for (int r = 0; r < 3; ++r) parts.push_back({"rank" + std::to_string(r), render_pieces(p, ranks[r])});
  const RenderState merged = merge_render_states(parts);
  expect_same_film(merged.film, whole.film);
  // The merged state resumed in a renderer: its image and half are the
  // whole render's bits.
  Session& s = *p.session;
  Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
  RenderStats stats;
  const ImageF resumed = r.render(&stats, {}, {}, &merged);
  EXPECT_EQ(stats.passes, 0);
  EXPECT_TRUE(same_bits(resumed, whole_image));
  Renderer w(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
  w.render(&stats, {}, {}, &whole);
  EXPECT_TRUE(same_bits(r.film().half_mean(), w.film().half_mean()));
}

TEST(StateMerge, WhatCannotBeAddedIsRefusedWithAPreciseError) {
  Prepared p = prepare(cornell(), 16);
  const RenderState a = render_pieces(p, {{0, 12}}), b = render_pieces(p, {{8, 16}});
  EXPECT_EQ(test::error_of([&] { merge_render_states({{"a.cst", a}, {"b.cst", b}}); }),
            "b.cst: its passes [8, 16) overlap a.cst's passes [0, 12) (both hold pass 8): merged states must hold "
            "disjoint passes");
  Prepared seeded = prepare(cornell(), 16, false, 3);
  const RenderState c = render_pieces(seeded, {{12, 16}});
  EXPECT_EQ(test::error_of([&] { merge_render_states({{"a.cst", a}, {"c.cst", c}}); }),
            "c.cst: seed 3, a.cst has seed 0");
  // The same scene with one more byte: another hash.
  std::ifstream in(cornell(), std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Prepared other = prepare(test::write_scene("cornell_changed.json", text + "\n"), 16);
  const RenderState d = render_pieces(other, {{12, 16}});
  EXPECT_TRUE(Contains(test::error_of([&] { merge_render_states({{"a.cst", a}, {"d.cst", d}}); }),
                       {"d.cst: made for scene hash ", ", a.cst for "}));
  Prepared adaptive = prepare(cornell(), 16, true);
  Session& s = *adaptive.session;
  Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, adaptive.settings);
  RenderStats stats;
  r.render(&stats);
  RenderState e = r.state();
  e.identity = a.identity;
  EXPECT_TRUE(Contains(test::error_of([&] { merge_render_states({{"a.cst", a}, {"e.cst", e}}); }),
                       {"e.cst: an adaptive render's state", "--no-adaptive"}));
  RenderState photons = a;
  photons.integrator = "x";
  EXPECT_TRUE(Contains(test::error_of([&] { merge_render_states({{"f.cst", photons}}); }),
                       {"f.cst: a state with the photon pass", "not sums of passes", "--caustics off"}));
}

// The caustica binary: render --passes twice, merge, and the same bits as
// one render (the merged image and the merged state resumed); damaged and
// mismatched files and bad options refused with one line.
TEST(StateMerge, TheCliMergesPassSubsetsToTheBitsOfOneRender) {
  const std::string dir = test::temp_dir();
  const std::string common = " --mode path --width 24 --caustics off --no-adaptive --exposure 0 -q --device '" +
                             test::device_spec() + "'";
  const std::string scene = "'" + cornell() + "'";
  auto render = [&](const std::string& args) { return test::run_cli("render " + scene + common + " " + args); };
  ASSERT_EQ(render("--spp 24 --checkpoint '" + dir + "/whole.cst' -o '" + dir + "/whole.pfm'").status, 0);
  test::CliResult r = render("--passes 0:9 --checkpoint '" + dir + "/a.cst' -o '" + dir + "/a.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  // The second part in two runs: a part resumes like any render.
  r = render("--passes 9:15 --checkpoint '" + dir + "/b.cst' -o '" + dir + "/b.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  r = render("--passes 9:24 --resume '" + dir + "/b.cst' --checkpoint '" + dir + "/b.cst' -o '" + dir + "/b.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::run_cli("merge -q '" + dir + "/a.cst' '" + dir + "/b.cst' -o '" + dir + "/merged.pfm' --state '" + dir +
                    "/merged.cst'");
  ASSERT_EQ(r.status, 0) << r.output;
  auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string whole = slurp(dir + "/whole.pfm");
  ASSERT_FALSE(whole.empty());
  EXPECT_TRUE(slurp(dir + "/merged.pfm") == whole) << "merged image differs from one render's";
  EXPECT_TRUE(slurp(dir + "/merged.cst") == slurp(dir + "/whole.cst")) << "merged state differs from one render's";
  r = render("--spp 24 --resume '" + dir + "/merged.cst' -o '" + dir + "/resumed.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(slurp(dir + "/resumed.pfm") == whole) << "the merged state resumed differs from one render";

  r = test::run_cli("merge '" + dir + "/a.cst' '" + dir + "/merged.cst' -o '" + dir + "/x.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.output, "caustica: error: " + dir + "/merged.cst: its passes [0, 24) overlap " + dir +
                          "/a.cst's passes [0, 9) (both hold pass 0): merged states must hold disjoint passes\n");
  const std::string b = slurp(dir + "/b.cst");
  std::ofstream(dir + "/cut.cst", std::ios::binary) << b.substr(0, b.size() / 2);
  r = test::run_cli("merge '" + dir + "/a.cst' '" + dir + "/cut.cst' -o '" + dir + "/x.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.output, {"cut.cst: truncated: " + std::to_string(b.size() / 2) + " bytes"})) << r.output;
  std::string flipped = b;
  flipped[flipped.size() / 2] ^= 0x10;
  std::ofstream(dir + "/flip.cst", std::ios::binary) << flipped;
  r = test::run_cli("merge '" + dir + "/a.cst' '" + dir + "/flip.cst' -o '" + dir + "/x.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.output, {"flip.cst: checksum mismatch", "the file is damaged"})) << r.output;
  r = test::run_cli("merge '" + dir + "/a.cst' -o '" + dir + "/x.png'");
  EXPECT_TRUE(Contains(r.output, {"expected a linear .pfm or .exr image"})) << r.output;

  r = test::run_cli("render " + scene + " --passes 8 -o '" + dir + "/x.pfm'");
  EXPECT_EQ(r.output, "caustica: error: --passes '8': expected START:END, whole numbers with 0 <= START < END "
                      "(passes [START, END))\n");
  r = test::run_cli("render " + scene + " --passes 0:8 --adaptive -o '" + dir + "/x.pfm'");
  EXPECT_TRUE(Contains(r.output, {"--passes 0:8: adaptive sampling plans each wave", "add --no-adaptive"}))
      << r.output;
  r = test::run_cli("render " + scene + " --passes 0:8 --spp 8 --no-adaptive -o '" + dir + "/x.pfm'");
  EXPECT_TRUE(Contains(r.output, {"--passes 0:8 and --spp: give one"})) << r.output;
}

}  // namespace
}  // namespace caustica
