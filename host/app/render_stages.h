// The stages of `caustica render` (run_render), split as Cycles splits a
// session's: the options read and checked (render_options.cpp), the run
// chosen and done (render_command.cpp: what the options and the scene
// decide, then one process or mpirun's ranks), and what it writes
// (render_outputs.cpp: images, passes, spp maps and state files while and
// after rendering; progress and the closing report on stderr).
// Internal to those three files.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/app/error_monitor.h"
#include "host/app/film_outputs.h"
#include "host/app/render_command.h"
#include "host/denoise/denoiser.h"
#include "host/denoise/film_denoise.h"
#include "host/image/tonemap.h"
#include "host/render/render_state.h"
#include "host/render/renderer.h"

namespace caustica {

// What the options and the prepared scene decided, before the first sample.
struct RenderPlan {
  std::unique_ptr<Session> session;
  bool distributed = false;           // mpirun with several ranks
  std::optional<RenderState> resume;  // --resume
  int resumed_passes = 0;             // the resumed state's
  std::optional<ImageF> reference;    // --reference, its size checked
  StateIdentity identity;             // with --checkpoint or --resume: what a state must match
  std::unique_ptr<Denoiser> denoiser;  // --denoise
  GuideMode guides = GuideMode::Clean;
  DisplaySettings display;
};

// The render done: on rank 0 only under mpirun.
struct RenderResult {
  ImageF image;
  const Renderer* shown = nullptr;   // whose film is written: this process's, or the ranks' sum
  std::unique_ptr<Renderer> summed;  // mpirun: owns that sum
  double seconds = 0.0;              // since the first sample, as the error monitor measured
};

// A render run to its end (render_scene): what it planned, traced and
// measured, kept for the caller. `caustica render` lets it go; the Python
// module holds it as a caustica.Render (host/app/held_render.h).
struct RenderRun {
  RenderPlan plan;
  RenderStats stats;
  std::unique_ptr<ErrorMonitor> monitor;
  std::optional<RenderResult> result;  // none on mpirun's ranks other than 0
  bool stopped_by_caller = false;      // RenderArgs::on_wave returned false
};

// Everything `caustica render` does, in order: the options checked, the
// plan, the render (this process or mpirun's ranks), the outputs written
// (RenderArgs::write_output), the error monitor finished, the report on
// stderr.
std::unique_ptr<RenderRun> render_scene(RenderArgs& args);

// Progress on stderr: a rewritten line on a terminal, one line a second
// otherwise; silent for renders that finish within a second.
class ProgressReporter {
 public:
  explicit ProgressReporter(bool enabled);
  void update(const PassProgress& p);
  void finish();
  void set_error_monitor(const ErrorMonitor* monitor) { monitor_ = monitor; }

 private:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool enabled_, tty_, printed_ = false;
  double last_ = 0.0;
  const ErrorMonitor* monitor_ = nullptr;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// The files a render writes: the image (path mode: the film's outputs,
// denoised, with its passes), the --spp-map heatmap and the --checkpoint
// state; while rendering (--write-every, --checkpoint-every) and at the end.
class RenderOutputs {
 public:
  RenderOutputs(const RenderArgs& args, const RenderPlan& plan);
  void write_images(const ImageF& image, const Film& film);
  // The state of `renderer`, unless the latest checkpoint holds as many passes.
  void write_checkpoint(const Renderer& renderer);
  // Between waves (the film holds whole waves only): what is due by `seconds`.
  void on_pass(const Renderer& renderer, const Film& film, double seconds);

 private:
  const RenderArgs& args_;
  const Session& session_;
  const StateIdentity& identity_;
  FilmOutputOptions film_options_;
  double last_write_ = 0.0, last_checkpoint_ = 0.0;
  int checkpoint_passes_ = -1;  // the latest checkpoint's
};

// The --report file's header: what was rendered, where, and what it cost
// before the first sample.
std::vector<std::pair<std::string, std::string>> report_header(const Session& session, const RenderArgs& args,
                                                               int resumed_passes);
// After the outputs are written: -v's statistics, --check-numerics, the
// warnings no render keeps silent, and what was written.
void report_render(const RenderArgs& args, const RenderPlan& plan, const RenderStats& stats,
                   const RenderResult& result, const ErrorMonitor& monitor);

}  // namespace caustica
