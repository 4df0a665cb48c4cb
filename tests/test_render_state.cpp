// Render state files (host/render/render_state.h): a render killed with
// SIGKILL after a checkpoint and resumed ends with the same bits as one never
// interrupted (the caustica binary, killed for real: uniform, adaptive, with
// the photon pass); the same in process for path (adaptive, photon pass
// auto and on), phong and binary; and every state that does not fit is
// refused with one precise error.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "host/app/session.h"
#include "host/error.h"
#include "host/render/render_state.h"
#include "host/render/renderer.h"
#include "tests/support/test_support.h"

extern char** environ;

namespace caustica {
namespace {

namespace fs = std::filesystem;
using test::Contains;

// Diffuse surfaces under an area light and a sphere light (no caster: no
// photon pass), 32 x 24 pixels.
const char* kPathScene = R"({"nbounces": 3, "rendermode": "pathtracer",
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
       "material": {"type": "diffuse", "albedo": [0.8, 0.3, 0.2]}},
      {"type": "cylinder", "center": [0.9, 0.4, 0.6], "axis": [0, 1, 0], "radius": 0.3, "height": 0.4,
       "material": {"type": "diffuse", "albedo": [0.2, 0.5, 0.8]}}]}})";

// Phong: a point light, a mirror sphere and a diffuse one, 24 x 16 pixels.
const char* kPhongScene = R"({"nbounces": 3, "rendermode": "phong",
  "camera": {"type": "pinhole", "width": 24, "height": 16, "position": [0, 0, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [0.1, 0.1, 0.2],
    "lightsources": [{"type": "pointlight", "position": [1, 2, -2], "intensity": [1, 1, 1]}],
    "shapes": [{"type": "sphere", "center": [-0.6, 0, 0], "radius": 0.5,
                "material": {"ks": 0.2, "kd": 0.8, "specularexponent": 20, "diffusecolor": [0.9, 0.2, 0.1],
                             "specularcolor": [1, 1, 1], "isreflective": true, "reflectivity": 0.5}},
               {"type": "sphere", "center": [0.7, 0, 0.3], "radius": 0.6,
                "material": {"ks": 0.1, "kd": 0.9, "specularexponent": 10, "diffusecolor": [0.2, 0.8, 0.3],
                             "specularcolor": [1, 1, 1]}}]}})";

using test::slurp;

std::string spew(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// --- the caustica binary, killed for real ---

// Starts `caustica args...` with its output in `log`; returns its pid.
pid_t spawn_caustica(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> words = {test::binary_path()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, 1, 2);
  pid_t pid = -1;
  const int failed = posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  return failed ? -1 : pid;
}

// `caustica render SCENE --spp SPP OPTIONS --device ...` as a word list.
std::vector<std::string> render_words(const std::string& scene, int spp, const std::vector<std::string>& options) {
  std::vector<std::string> words = {"render", scene, "--mode", "path", "--spp", std::to_string(spp)};
  words.insert(words.end(), options.begin(), options.end());
  words.insert(words.end(), {"--device", test::device_spec()});
  return words;
}
// The same for the shell (test::run_cli).
std::string shell_words(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words) line += (line.empty() ? "'" : " '") + w + "'";
  return line;
}
std::string render_args(const std::string& scene, int spp, bool adaptive) {
  return shell_words(render_words(scene, spp, {"--caustics", "off", adaptive ? "--adaptive" : "--no-adaptive"}));
}

// Renders with a checkpoint after every wave and kills the process with
// SIGKILL as soon as a checkpoint holds at least `kill_after` passes;
// resumes; compares with an uninterrupted render. A device fast enough to
// finish before the kill gets more samples.
void expect_kill_and_resume_same_bits(const std::string& scene, const std::vector<std::string>& options,
                                      int kill_after, int first_spp) {
  const std::string dir = test::temp_dir();
  const std::string state = dir + "/state.cst";
  int spp = first_spp;
  int killed_at = 0;
  for (int attempt = 0; attempt < 3 && killed_at == 0; ++attempt, spp *= 8) {
    fs::remove(state);
    fs::remove(dir + "/killed.pfm");
    std::vector<std::string> words = render_words(scene, spp, options);
    words.insert(words.end(), {"-q", "--checkpoint", state, "--checkpoint-every", "0.001", "-o", dir + "/killed.pfm"});
    const pid_t pid = spawn_caustica(words, dir + "/killed.log");
    ASSERT_GT(pid, 0) << "cannot start " << test::binary_path();
    int status = 0;
    bool ended = false;
    for (;;) {
      if (waitpid(pid, &status, WNOHANG) == pid) {
        ended = true;  // before any kill: finished, or failed
        break;
      }
      if (fs::exists(state)) {
        // Renamed into place whole: whatever is there is a complete state.
        const RenderState s = read_render_state(state);
        if (s.film.passes >= kill_after) {
          ASSERT_EQ(kill(pid, SIGKILL), 0);
          ASSERT_EQ(waitpid(pid, &status, 0), pid);
          break;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (ended) {
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir + "/killed.log");
      continue;  // too fast for this many samples: more
    }
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    EXPECT_FALSE(fs::exists(dir + "/killed.pfm")) << "the killed render wrote its image";
    killed_at = read_render_state(state).film.passes;
  }
  spp /= 8;
  ASSERT_GT(killed_at, 0) << "every render finished before a checkpoint of " << kill_after << " passes";
  ASSERT_LT(killed_at, spp);
  std::printf("[measure] killed at %d of %d spp\n", killed_at, spp);

  const test::CliResult resumed = test::run_cli(shell_words(render_words(scene, spp, options)) + " --resume '" +
                                                state + "' -o '" + dir + "/resumed.pfm'");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_TRUE(Contains(resumed.output, {"resumed from " + std::to_string(killed_at) + " spp"}));
  const test::CliResult whole =
      test::run_cli(shell_words(render_words(scene, spp, options)) + " -q -o '" + dir + "/whole.pfm'");
  ASSERT_EQ(whole.status, 0) << whole.output;
  const std::string a = slurp(dir + "/whole.pfm"), b = slurp(dir + "/resumed.pfm");
  ASSERT_GT(a.size(), 32u * 24u * 12u);
  EXPECT_TRUE(a == b) << "the resumed render's bits differ from the uninterrupted render's";
}

// 32 x 24 pixels: waves of 128 passes from 256 on, killed at 768 or later,
// far past adaptive sampling's first 16 spp. Oclgrind: 64 spp, killed
// after 16.
TEST(RenderState, KilledAndResumedPathRenderHasTheSameBits) {
  expect_kill_and_resume_same_bits(test::write_scene("lit.json", kPathScene), {"--caustics", "off", "--no-adaptive"},
                                   int(test::sized(768, 16)), int(test::sized(2048, 64)));
}
TEST(RenderState, KilledAndResumedAdaptiveRenderHasTheSameBits) {
  expect_kill_and_resume_same_bits(test::write_scene("lit.json", kPathScene), {"--caustics", "off", "--adaptive"},
                                   int(test::sized(768, 16)), int(test::sized(2048, 64)));
}
// The photon pass, `auto`: at 48 x 36 a map every 28 passes, then the
// interval the errors balance at; killed past the second map.
TEST(RenderState, KilledAndResumedPhotonPassRenderHasTheSameBits) {
  expect_kill_and_resume_same_bits(test::source_dir() + "/scenes/caustics.json",
                                   {"--caustics", "auto", "--width", "48"}, int(test::sized(40, 2)),
                                   int(test::sized(256, 8)));
}

// --- in process ---

struct Prepared {
  std::unique_ptr<Session> session;
  RenderSettings settings;
};

Prepared prepare(const std::string& scene, RenderMode mode, int passes, bool adaptive,
                 CausticsMode caustics = CausticsMode::Off, int width = 0) {
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  o.mode = mode;
  o.spp = passes;
  o.caustics = caustics;
  o.width = width;  // 0: the camera's
  o.adaptive = adaptive;
  Prepared p;
  p.session = prepare_session(o);
  p.settings = p.session->settings;
  p.settings.passes = passes;  // phong and binary too (one pass unless asked)
  return p;
}

StateIdentity identity_of(const Session& s, const RenderSettings& settings) {
  return render_identity(scene_hash(s.scene), s.mode, settings, "spatial");
}

// Renders `passes` passes whole, and again from the state written after
// the wave that reached `save_at` passes (through a state file), with a
// new renderer: the same bits and counts.
void expect_resume_in_process_same_bits(const std::string& scene, RenderMode mode, int passes, int save_at,
                                        bool adaptive, CausticsMode caustics = CausticsMode::Off, int width = 0) {
  Prepared p = prepare(scene, mode, passes, adaptive, caustics, width);
  ASSERT_EQ(p.settings.caustics, caustics != CausticsMode::Off);
  Session& s = *p.session;
  const std::string path = test::temp_dir() + "/state.cst";
  ImageF whole;
  std::vector<uint32_t> whole_spp;
  {
    Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
    int saved = 0;
    RenderStats stats;
    whole = r.render(&stats, {}, [&](const Film& film, double) {
      if (saved == 0 && film.passes() >= save_at) {
        RenderState state = r.state();
        state.identity = identity_of(s, p.settings);
        write_render_state(path, state);
        saved = film.passes();
      }
      return true;
    });
    ASSERT_GT(saved, 0);
    ASSERT_LT(saved, passes);
    if (p.settings.caustics && mode == RenderMode::Path) {
      // The pass stayed on, with maps on both sides of the state.
      EXPECT_TRUE(stats.caustics_decision.find("off") == std::string::npos) << stats.caustics_decision;
      EXPECT_GE(stats.photon_maps, 3u) << stats.caustics_decision;
      std::printf("[measure] %u photon maps in %d passes, saved at %d%s%s\n", stats.photon_maps, passes, saved,
                  stats.caustics_decision.empty() ? "" : ": ", stats.caustics_decision.c_str());
    }
    whole_spp = r.film().pixel_spp();
  }
  Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
  const RenderState state = read_render_state(path);
  EXPECT_EQ(state.adaptive.has_value(), adaptive);
  check_render_state(path, state, identity_of(s, p.settings));
  RenderStats stats;
  const ImageF resumed = r.render(&stats, {}, {}, &state);
  EXPECT_EQ(stats.passes, passes - state.film.passes);
  EXPECT_EQ(r.film().passes(), passes);
  EXPECT_EQ(r.film().pixel_spp(), whole_spp);
  ASSERT_EQ(resumed.rgb.size(), whole.rgb.size());
  EXPECT_EQ(0, std::memcmp(resumed.rgb.data(), whole.rgb.data(), whole.rgb.size() * sizeof(float)));
}

TEST(RenderState, ResumedInProcessAdaptivePathHasTheSameBits) {
  // 32 x 24 pixels: waves of 128 passes from 256 on. The sampler reads the
  // film again once its passes grew by a quarter: at 640, not at 768, so a
  // state saved at 768 resumes with weights cached at 640 (and the pixels'
  // ray counts they weigh).
  // (Oclgrind: 64 passes, saved at 32.)
  expect_resume_in_process_same_bits(test::write_scene("lit.json", kPathScene), RenderMode::Path,
                                     int(test::sized(1024, 64)), int(test::sized(768, 32)), true);
}

// The photon pass: SPPM statistics, visible points, the latest map (its grid
// built again) and `auto`'s schedule. scenes/caustics.json at 48 x 36.
TEST(RenderState, ResumedInProcessPhotonPassHasTheSameBits) {
  const std::string scene = test::source_dir() + "/scenes/caustics.json";
  // auto: a map every 28 passes here, then the interval the errors balance
  // at; states between maps, at a map and after the decisions.
  for (int save_at : {1, 2, 16, 29, 40, 70}) {
    SCOPED_TRACE("auto, saved at " + std::to_string(save_at));
    expect_resume_in_process_same_bits(scene, RenderMode::Path, 96, save_at, true, CausticsMode::Auto, 48);
  }
  for (int save_at : {3, 20}) {
    SCOPED_TRACE("on, saved at " + std::to_string(save_at));
    expect_resume_in_process_same_bits(scene, RenderMode::Path, 32, save_at, false, CausticsMode::On, 48);
  }
  // Phong with --caustics on: a map every pass, gathered within a shared
  // radius that shrinks with the map count.
  SCOPED_TRACE("phong");
  expect_resume_in_process_same_bits(scene, RenderMode::Phong, 8, 3, false, CausticsMode::On, 48);
}

TEST(RenderState, ResumedInProcessPhongHasTheSameBits) {
  expect_resume_in_process_same_bits(test::write_scene("phong.json", kPhongScene), RenderMode::Phong, 4, 2, false);
}

TEST(RenderState, ResumedInProcessBinaryHasTheSameBits) {
  expect_resume_in_process_same_bits(test::write_scene("phong.json", kPhongScene), RenderMode::Binary, 3, 1, false);
}

// The same-bits property of resume against states altered consistently
// with their checksum (issue 38: a header of 0 passes that still holds
// sums, of 2^31 - 1 passes, a pass set that does not start at 0): every
// count, size, flag and range of a real state is changed in turn, the
// state encoded and read back as a file would be, and resumed. Each either
// resumes to the bits of the uninterrupted render, or is refused with a
// caustica::Error. (The sums themselves are data: a consistent change of
// one, or of every count with the pass count, so that the counts agree with
// each other but describe other sums, is a different render that no check
// can tell from this one; the checksum is their guard against damage.
// fuzz/fuzz_state.cpp reaches the same fields under the sanitizers.)
TEST(RenderState, AlteredStatesResumeToTheSameBitsOrAreRefused) {
  const std::string scene = test::write_scene("lit.json", kPathScene);
  for (bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive ? "adaptive" : "uniform");
    const int passes = 8;
    Prepared p = prepare(scene, RenderMode::Path, passes, adaptive, CausticsMode::Off, 8);
    Session& s = *p.session;
    const StateIdentity identity = identity_of(s, p.settings);
    ImageF whole;
    RenderState saved;
    {
      Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
      RenderStats stats;
      whole = r.render(&stats, {}, [&](const Film& film, double) {
        if (saved.identity.empty() && film.passes() >= 2 && film.passes() < passes) {
          saved = r.state();
          saved.identity = identity;
        }
        return true;
      });
    }
    ASSERT_FALSE(saved.identity.empty());
    using Change = std::function<void(RenderState&)>;
    const std::vector<std::pair<std::string, Change>> changes = {
        {"as saved", [](RenderState&) {}},
        {"passes 0 (sums kept)", [](RenderState& x) { x.film.passes = 0; }},
        {"passes + 1", [](RenderState& x) { x.film.passes += 1; }},
        {"passes - 1", [](RenderState& x) { x.film.passes -= 1; }},
        {"passes 2^31 - 1", [](RenderState& x) { x.film.passes = 2147483647; }},
        {"passes -1", [](RenderState& x) { x.film.passes = -1; }},
        {"pass set [1, N+1)", [](RenderState& x) { x.film.held = PassSet::range(1, x.film.passes + 1); }},
        {"pass set [0, N+1)", [](RenderState& x) { x.film.held = PassSet::range(0, x.film.passes + 1); }},
        {"pass set empty", [](RenderState& x) { x.film.held = PassSet(); }},
        {"passes and pass set + 1",
         [](RenderState& x) {
           x.film.passes += 1;
           x.film.held = PassSet::range(0, x.film.passes);
         }},
        {"every pixel + 1 sample",
         [](RenderState& x) {
           for (uint32_t& n : x.film.spp) n += 1;
         }},
        {"per-pixel flag flipped", [](RenderState& x) { x.film.per_pixel = !x.film.per_pixel; }},
        {"one pixel fewer", [](RenderState& x) { x.film.spp.pop_back(); }},
        {"half starts short", [](RenderState& x) { x.film.half_start.pop_back(); }},
        {"half start past the passes", [](RenderState& x) { x.film.half_start[0] = uint32_t(x.film.passes + 5); }},
        {"ray counts short", [](RenderState& x) { x.film.pixel_rays.pop_back(); }},
        {"counters short", [](RenderState& x) { x.film.counters.pop_back(); }},
        {"sums short", [](RenderState& x) { x.film.accumulated.resize(x.film.accumulated.size() - 2); }},
        {"sums long", [](RenderState& x) { x.film.accumulated.resize(x.film.accumulated.size() + 2); }},
        {"no sums", [](RenderState& x) { x.film.accumulated.clear(); }},
        {"adaptive sampler dropped", [](RenderState& x) { x.adaptive.reset(); }},
        {"adaptive sampler added",
         [](RenderState& x) {
           if (!x.adaptive) x.adaptive = AdaptiveSamplerState{std::vector<double>(x.film.spp.size(), 1.0), 1};
         }},
        {"weights cached after the film's passes",
         [](RenderState& x) {
           if (x.adaptive) x.adaptive->weights_passes = x.film.passes + 1;
         }},
        {"weights cached at -1",
         [](RenderState& x) {
           if (x.adaptive) x.adaptive->weights_passes = -1;
         }},
        {"weights short",
         [](RenderState& x) {
           if (x.adaptive && !x.adaptive->weights.empty()) x.adaptive->weights.pop_back();
         }},
        {"a weight NaN",
         [](RenderState& x) {
           if (x.adaptive && !x.adaptive->weights.empty()) x.adaptive->weights[0] = std::nan("");
         }},
        {"integrator state added", [](RenderState& x) { x.integrator = "photon pass"; }},
        {"identity entry dropped", [](RenderState& x) { x.identity.pop_back(); }},
        {"identity width doubled",
         [](RenderState& x) {
           for (auto& [name, value] : x.identity)
             if (name == "width") value = std::to_string(2 * std::stoi(value));
         }},
    };
    int resumed_same = 0, refused = 0;
    for (const auto& [what, change] : changes) {
      SCOPED_TRACE(what);
      RenderState altered = saved;
      change(altered);
      const std::string path = spew(test::temp_dir() + "/altered.cst", encode_render_state(altered));
      try {
        const RenderState state = read_render_state(path);
        check_render_state(path, state, identity);
        Renderer r(*s.runtime, *s.device_scene, s.mode, s.program.program, p.settings);
        RenderStats stats;
        const ImageF resumed = r.render(&stats, {}, {}, &state);
        EXPECT_EQ(r.film().passes(), passes);
        ASSERT_EQ(resumed.rgb.size(), whole.rgb.size());
        EXPECT_EQ(0, std::memcmp(resumed.rgb.data(), whole.rgb.data(), whole.rgb.size() * sizeof(float)))
            << "resumed, with other bits than the uninterrupted render's";
        ++resumed_same;
      } catch (const Error& e) {
        ++refused;
        std::printf("[refused] %s: %s\n", what.c_str(), e.what());
      }
    }
    std::printf("[measure] %s: %d altered states resumed to the same bits, %d refused\n",
                adaptive ? "adaptive" : "uniform", resumed_same, refused);
    EXPECT_GE(resumed_same, 1);  // the state as saved
  }
}

// --- refusals ---

// A real state (binary mode: quick) and the identity it was made with.
struct Saved {
  std::string bytes;
  StateIdentity identity;
};

Saved binary_state(const std::string& scene) {
  Prepared p = prepare(scene, RenderMode::Binary, 1, false);
  Session& s = *p.session;
  RenderStats stats;
  s.renderer->render(&stats);
  RenderState state = s.renderer->state();
  state.identity = identity_of(s, s.settings);
  return {encode_render_state(state), state.identity};
}

TEST(RenderState, DamagedFilesAreRefusedWithAPreciseError) {
  const Saved saved = binary_state(test::write_scene("phong.json", kPhongScene));
  const std::string dir = test::temp_dir();
  // Round trip first: the bytes decode to what was encoded.
  const RenderState back = read_render_state(spew(dir + "/good.cst", saved.bytes));
  EXPECT_EQ(back.identity, saved.identity);
  EXPECT_EQ(back.film.passes, 1);
  EXPECT_EQ(encode_render_state(back), saved.bytes);

  const size_t n = saved.bytes.size();
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/cut.cst", saved.bytes.substr(0, n - 9))); }),
                       {"cut.cst: truncated: " + std::to_string(n - 9) + " bytes, its header says " +
                        std::to_string(n)}));
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/stub.cst", saved.bytes.substr(0, 20))); }),
                       {"stub.cst: truncated: 20 bytes"}));
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/tiny.cst", saved.bytes.substr(0, 5))); }),
                       {"tiny.cst: truncated: 5 bytes"}));
  std::string flipped = saved.bytes;
  flipped[n / 2] = char(flipped[n / 2] ^ 0x10);
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/flip.cst", flipped)); }),
                       {"flip.cst: checksum mismatch", "the file is damaged"}));
  std::string version = saved.bytes;
  version[16] = 1;  // the version follows the 16-byte magic: version 1 had no pass set
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/v1.cst", version)); }),
                       {"v1.cst: state file version 1, this caustica reads version 2"}));
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(spew(dir + "/long.cst", saved.bytes + "xyz")); }),
                       {"long.cst: 3 bytes after the state's end"}));
  const std::string scene_file = test::write_scene("other.json", kPathScene);
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(scene_file); }),
                       {"other.json: not a caustica state file"}));
  EXPECT_TRUE(Contains(test::error_of([&] { read_render_state(dir + "/none.cst"); }),
                       {"none.cst: state file not found"}));
}

TEST(RenderState, StatesOfOtherScenesOrSettingsAreRefused) {
  const std::string phong = test::write_scene("phong.json", kPhongScene);
  const Saved saved = binary_state(phong);
  const RenderState state = decode_render_state(saved.bytes, "s.cst");
  EXPECT_NO_THROW(check_render_state("s.cst", state, saved.identity));

  // Another scene: one byte of the file changed.
  std::string other_text = kPhongScene;
  other_text.replace(other_text.find("0.1, 0.1, 0.2"), 13, "0.1, 0.1, 0.3");
  Scene a, b;
  a.source_path = phong;
  b.source_path = test::write_scene("other.json", other_text);
  char hash_a[24], hash_b[24];
  std::snprintf(hash_a, sizeof hash_a, "%016llx", (unsigned long long)scene_hash(a));
  std::snprintf(hash_b, sizeof hash_b, "%016llx", (unsigned long long)scene_hash(b));
  StateIdentity other = saved.identity;
  ASSERT_EQ(other[0].first, "scene hash");
  EXPECT_EQ(other[0].second, hash_a);  // the scene file's bytes (no meshes, no textures)
  other[0].second = hash_b;
  EXPECT_TRUE(Contains(test::error_of([&] { check_render_state("s.cst", state, other); }),
                       {"s.cst: made for scene hash " + std::string(hash_a) + ", this scene is " + hash_b}));

  // Other settings: the first difference is named.
  RenderSettings settings;
  settings.width = 24;
  settings.height = 16;
  const uint64_t hash = scene_hash(a);
  auto refused = [&](RenderMode mode, const RenderSettings& s, const std::string& bvh) {
    return test::error_of([&] { check_render_state("s.cst", state, render_identity(hash, mode, s, bvh)); });
  };
  EXPECT_NO_THROW(
      check_render_state("s.cst", state, render_identity(hash, RenderMode::Binary, settings, "spatial")));
  RenderSettings wide = settings;
  wide.width = 64;
  EXPECT_TRUE(Contains(refused(RenderMode::Binary, wide, "spatial"), {"s.cst: width 24 in the state, 64 asked"}));
  EXPECT_TRUE(
      Contains(refused(RenderMode::Phong, settings, "spatial"), {"s.cst: mode binary in the state, phong asked"}));
  EXPECT_TRUE(Contains(refused(RenderMode::Binary, settings, "fast"), {"s.cst: bvh spatial in the state, fast asked"}));
  // Path settings: a path state against another seed, sampler, adaptive sampling.
  RenderSettings path = settings;
  path.adaptive = true;
  RenderState path_state = state;
  path_state.identity = render_identity(hash, RenderMode::Path, path, "spatial");
  auto path_refused = [&](const RenderSettings& s) {
    return test::error_of(
        [&] { check_render_state("p.cst", path_state, render_identity(hash, RenderMode::Path, s, "spatial")); });
  };
  RenderSettings seeded = path;
  seeded.seed = 7;
  EXPECT_TRUE(Contains(path_refused(seeded), {"p.cst: seed 0 in the state, 7 asked"}));
  RenderSettings uniform = path;
  uniform.adaptive = false;
  EXPECT_TRUE(Contains(path_refused(uniform), {"p.cst: adaptive on in the state, off asked"}));
  RenderSettings independent = path;
  independent.sampler = SAMPLER_INDEPENDENT;
  EXPECT_TRUE(Contains(path_refused(independent), {"p.cst: sampler sobol in the state, independent asked"}));
  RenderSettings share = path;
  share.adaptive_options.uniform_share = 0.5;
  EXPECT_TRUE(Contains(path_refused(share), {"p.cst: adaptive uniform share 0.25 in the state, 0.5 asked"}));
}

// Through the binary: a state of another size, seed or spp than asked, each
// one line naming the file and what differs.
TEST(RenderState, TheCliRefusesWhatItCannotResume) {
  const std::string dir = test::temp_dir();
  const std::string scene = test::write_scene("lit.json", kPathScene);
  const std::string state = dir + "/s.cst";
  const std::string base = render_args(scene, 32, true) + " -q";
  test::CliResult r = test::run_cli(base + " --checkpoint '" + state + "' -o '" + dir + "/a.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_EQ(read_render_state(state).film.passes, 32);

  r = test::run_cli(base + " --width 16 --resume '" + state + "' -o '" + dir + "/b.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.output, "caustica: error: " + state + ": width 32 in the state, 16 asked\n");
  r = test::run_cli(render_args(scene, 16, true) + " -q --resume '" + state + "' -o '" + dir + "/b.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.output, "caustica: error: " + state + ": holds passes [0, 32), past the 16 asked (--spp)\n");
  r = test::run_cli(render_args(scene, 32, true) + " -q --seed 3 --resume '" + state + "' -o '" + dir + "/b.pfm'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.output, "caustica: error: " + state + ": seed 0 in the state, 3 asked\n");
  // The same spp: nothing left to render, the image is the state's.
  r = test::run_cli(base + " --resume '" + state + "' -o '" + dir + "/c.pfm'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(slurp(dir + "/a.pfm") == slurp(dir + "/c.pfm"));
}

}  // namespace
}  // namespace caustica

namespace caustica {
namespace {

// Issue 38: state files keep what they promise. No option may make a render
// overwrite its own output with its state, save to a device or to an empty
// name, resume passes that leave a gap, or merge a state whose header does
// not describe its data; passes near 2^31 cost what they render.
TEST(RenderState, StateFilesKeepWhatTheyPromise) {
  if (test::on_simulator()) GTEST_SKIP() << "CLI renders: the other tests cover the simulator";
  const std::string dir = test::temp_dir();
  const std::string args = "render '" + test::source_dir() + "/scenes/cornell_box.json' --width 16 --no-adaptive "
                           "--caustics off --device '" + test::device_spec() + "' -q ";
  auto refused = [&](const std::string& rest, std::initializer_list<std::string> parts) {
    const test::CliResult r = test::run_cli(args + rest);
    EXPECT_NE(r.status, 0) << rest << ": " << r.output;
    EXPECT_TRUE(test::Contains(r.output, parts)) << rest << ": " << r.output;
  };
  refused("--spp 2 --checkpoint '" + dir + "/out.pfm' -o '" + dir + "/out.pfm'", {"name the same file"});
  refused("--spp 2 --checkpoint '" + dir + "/./out.exr' -o '" + dir + "/out.exr'", {"name the same file"});
  ASSERT_EQ(::symlink("/dev/full", (dir + "/full.cst").c_str()), 0);
  refused("--spp 2 --checkpoint '" + dir + "/full.cst' -o '" + dir + "/a.pfm'", {"full.cst", "not a regular file"});
  refused("--spp 2 --checkpoint '' -o '" + dir + "/a.pfm'", {"--checkpoint", "expected a file name"});
  refused("--spp 2 -o ''", {"expected a file name"});
  EXPECT_FALSE(std::ifstream(dir + "/out.pfm").good()) << "nothing written";
  // A state of passes [2, 4) resumes only where the render begins at 2.
  ASSERT_EQ(test::run_cli(args + "--passes 2:4 --checkpoint '" + dir + "/p.cst' -o '" + dir + "/p.pfm'").status, 0);
  refused("--spp 4 --resume '" + dir + "/p.cst' -o '" + dir + "/r.pfm'",
          {"p.cst", "holds passes [2, 4)", "does not begin at pass 0", "caustica merge"});
  EXPECT_EQ(test::run_cli(args + "--passes 2:6 --resume '" + dir + "/p.cst' -o '" + dir + "/r.pfm'").status, 0);
  // Headers altered consistently with the checksum: counts that do not
  // describe the data are refused by merge.
  RenderState state = read_render_state(dir + "/p.cst");
  RenderState no_passes = state;
  no_passes.film.passes = 0;
  no_passes.film.held = PassSet();
  std::fill(no_passes.film.spp.begin(), no_passes.film.spp.end(), 0u);
  write_render_state(dir + "/none.cst", no_passes);
  RenderState huge = state;
  huge.film.passes = 2147483647;
  write_render_state(dir + "/huge.cst", huge);
  for (const char* name : {"none.cst", "huge.cst"}) {
    const test::CliResult r = test::run_cli("merge '" + dir + "/" + name + "' -q -o '" + dir + "/m.pfm'");
    EXPECT_NE(r.status, 0) << name << ": " << r.output;
    EXPECT_TRUE(test::Contains(r.output, {name, "film:"})) << r.output;
  }
  // One pass at index 2^31 - 2 renders in the time of one pass.
  const test::CliResult last =
      test::run_cli(args + "--passes 2147483646:2147483647 -o '" + dir + "/last.pfm'");
  EXPECT_EQ(last.status, 0) << last.output;
}

}  // namespace
}  // namespace caustica
