// `caustica render`: options, the render itself, progress on stderr, the
// image written at the end (and while rendering with --write-every), the
// error against run time (--report, --reference, --plot, --target-error;
// host/app/error_monitor.h), and its state saved and resumed (--checkpoint,
// --resume; host/render/render_state.h). Its stages: render_options.cpp,
// render_command.cpp and render_outputs.cpp (render_stages.h says which
// does what).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "host/app/rank_group.h"
#include "host/app/session.h"

// CLI11 is declared, not included: it is parsed only by the units that
// add options (docs/howto.md, "Build and test time").
namespace CLI {
class App;
}  // namespace CLI

namespace caustica {

struct RenderState;

// Between waves, for a caller that keeps the render in memory (the Python
// module's callback): the film's samples per pixel, the seconds since the
// first sample and the latest estimated relMSE (measured after 1, 2, 4, ...
// passes: host/app/error_monitor.h). Returning false stops the render
// there, with every wave it finished.
struct WaveDone {
  int spp = 0;
  double seconds = 0.0;
  std::optional<double> error_estimate;
};
using WaveHook = std::function<bool(const WaveDone&)>;

struct RenderArgs {
  SessionOptions session;
  std::string mode, output, tonemap;  // tonemap default: linear, or aces in path mode
  std::optional<float> exposure;
  std::optional<float> gamma;  // default: kCourseworkDisplayGamma, or kPathDisplayGamma in path mode
  bool verbose = false, quiet = false;
  double write_every_s = 0.0;  // path: also write the image while rendering
  std::string report, reference, plot;
  std::string spp_map;  // path: the per-pixel sample counts as a heatmap (.png/.svg)
  double target_error = 0.0;
  bool no_error_estimate = false;
  // Render state files (host/render/render_state.h): written every
  // checkpoint_every_s seconds (between waves) and at the end; resumed from.
  std::string checkpoint, resume;
  std::optional<double> checkpoint_every_s;  // default kDefaultCheckpointSeconds
  // --passes START:END: a render of passes [START, END) only, with their
  // absolute indices (its state merges with others': `caustica merge`).
  std::string passes;
  // Path: --denoise (the main image of every output is OIDN's), its
  // quality, and --aov-dir (each pass as its own file).
  bool denoise = false;
  std::string denoise_quality = "high";
  std::string denoise_guides = "auto";  // --denoise-guides
  std::string aov_dir;
  // Under mpirun (host/main.cpp): the ranks; nullptr or one rank: a
  // single-process render.
  RankGroup* ranks = nullptr;
  // A caller that keeps the render in memory (the Python module,
  // host/app/held_render.h): with write_output false nothing is written at
  // the end but what an option names (-o given, --checkpoint...); on_wave
  // runs between waves (one process only); resume_state is resumed instead
  // of reading --resume's file (`resume` then only names it in messages).
  bool write_output = true;
  WaveHook on_wave;
  std::shared_ptr<const RenderState> resume_state;
};

inline constexpr double kDefaultCheckpointSeconds = 60.0;

// The `render` subcommand's options, bound to `args`.
CLI::App* add_render_command(CLI::App& app, RenderArgs& args);
// Every option's value and combination, before anything is read (the
// command line's fuzz target runs it too); fills in what they decide
// (the output's default name, the session's mode, pass range, aux passes).
void check_render_options(RenderArgs& args);
int run_render(RenderArgs& args);
// "START:END" (--passes): [START, END), 0 <= START < END; throws caustica::Error.
std::pair<int, int> parse_pass_range(const std::string& text);
// Under mpirun with several ranks (render_parts.cpp): refuses what ranks
// do not do, before anything is read; picks this rank's --device entry;
// silences every rank but 0. "mpirun with N ranks", for messages.
void check_distributed_options(RenderArgs& args);
std::string ranks_text(const RenderArgs& args);

}  // namespace caustica
