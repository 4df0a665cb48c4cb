// One render of a scene in one mode: the device scene, the mode's integrator,
// a film and the pass driver, put together. What `caustica render`, the tests
// and the bench's render timing call. A render may start from a saved state
// (host/render/render_state.h) and its state may be taken between waves
// (from a pass-done callback, or after render returns).
#pragma once

#include <memory>
#include <optional>

#include "host/render/device_scene.h"
#include "host/render/film.h"
#include "host/render/integrator.h"
#include "host/render/pass_driver.h"
#include "host/render/render_state.h"

namespace caustica {

class Renderer {
 public:
  Renderer(Runtime& runtime, const DeviceScene& scene, RenderMode mode, const cl::Program& program,
           const RenderSettings& settings);

  // Clears the film (or, given `resume`, restores it and the adaptive
  // sampler from that state), renders until the film holds settings.passes
  // passes (or until settings.time_limit_s), returns the mean.
  ImageF render(RenderStats* stats, const ProgressCallback& progress = {}, const PassDoneCallback& pass_done = {},
                const RenderState* resume = nullptr);
  // render() in steps, for a caller that runs the passes in pieces (MPI
  // ranks, host/app/mpi_render.h): begin clears the film (or restores
  // `resume`), run adds passes (PassDriver::run: absolute pass indices,
  // the film is not cleared), finish reads the mean and collects stats.
  void begin(const RenderState* resume = nullptr);
  // From the next begin() on, every wave is shared among processes
  // (pass_driver.h's WaveShare).
  void share_waves(WaveShare share) { share_ = std::move(share); }
  // The adaptive sampler's state now (none without adaptive sampling).
  std::optional<AdaptiveSamplerState> adaptive_state() const;
  void run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress = {},
           const PassDoneCallback& pass_done = {});
  ImageF finish(RenderStats* stats);
  // The film's, the adaptive sampler's and the integrator's state (the
  // photon pass's), between waves; its identity is left to the caller
  // (render_identity).
  RenderState state() const;
  // Throws caustica::Error, saying what differs, when `state` cannot be
  // resumed by this renderer (sizes, the adaptive sampler's presence and
  // state, a pass range that does not start where the render does or ends
  // past it); render(..., &state) checks it too.
  void check_state(const RenderState& state) const;

  Integrator& integrator() { return *integrator_; }
  Film& film() { return *film_; }
  const Film& film() const { return *film_; }
  const RenderSettings& settings() const { return settings_; }

 private:
  Runtime& runtime_;
  RenderMode mode_;
  RenderSettings settings_;
  StageLauncher launcher_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<Film> film_;
  std::unique_ptr<PassDriver> driver_;  // the latest render's
  WaveShare share_;

  // Runs f, turning OpenCL errors into caustica::Error naming the device.
  template <typename F>
  auto on_device(F&& f) -> decltype(f());
};

}  // namespace caustica
