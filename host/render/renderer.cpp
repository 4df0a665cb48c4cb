#include "host/render/renderer.h"

#include <cmath>

#include <chrono>

#include "host/cl/runtime.h"
#include "host/error.h"

namespace caustica {

Renderer::Renderer(Runtime& runtime, const DeviceScene& scene, RenderMode mode, const cl::Program& program,
                   const RenderSettings& settings)
    : runtime_(runtime), mode_(mode), settings_(settings), launcher_(runtime, settings.local_size) {
  if (settings.width <= 0 || settings.height <= 0) throw Error("render: image size must be positive");
  if (settings.passes <= 0) throw Error("render: the number of passes must be positive");
  try {
    integrator_ = make_integrator(mode, launcher_, scene, program, settings);
    FilmOptions film;
    film.width = settings.width;
    film.height = settings.height;
    film.half_buffer = settings.half_buffer || settings.adaptive;
    film.aux_passes = settings.aux_passes && mode == RenderMode::Path;
    film_ = std::make_unique<Film>(runtime, program, film);
  } catch (const cl::Error& e) {
    throw Error(std::string("cannot set up the renderer on ") + runtime.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

void Renderer::check_state(const RenderState& state) const {
  film_->check_state(state.film);
  if (settings_.adaptive != state.adaptive.has_value())
    throw Error(std::string("render state: ") +
                (state.adaptive ? "an adaptive sampler's state" : "no adaptive sampler's state") +
                " for a render " + (settings_.adaptive ? "with" : "without") + " adaptive sampling");
  if (state.adaptive) {
    const AdaptiveSamplerState& a = *state.adaptive;
    if (!a.weights.empty() && a.weights.size() != film_->pixel_count())
      throw Error("render state: " + std::to_string(a.weights.size()) + " adaptive weights for " +
                  std::to_string(film_->pixel_count()) + " pixels");
    if (a.weights_passes < 0 || a.weights_passes > state.film.passes)
      throw Error("render state: adaptive weights taken at pass " + std::to_string(a.weights_passes) +
                  " of a film of " + std::to_string(state.film.passes));
    for (size_t i = 0; i < a.weights.size(); ++i)
      if (!(std::isfinite(a.weights[i]) && a.weights[i] >= 0.0))
        throw Error("render state: adaptive weight " + std::to_string(i) + " is not a finite non-negative number");
  }
  // The render continues the state's passes up to its own end: the state
  // must hold the start of the render's range, or passes would be missing
  // (a state of passes [2, 4) resumed to --spp 4 wrote a 2-spp image).
  const PassSet& held = state.film.held;
  const int first = settings_.first_pass;
  if (!held.empty() && !(held == PassSet::range(first, held.end())))
    throw Error("holds " + held.describe() + ", which does not begin at pass " + std::to_string(first) +
                " where this render does: render the passes before it (--passes " + std::to_string(first) + ":" +
                std::to_string(first < held.first() ? held.first() : first) +
                " --checkpoint) and `caustica merge` the states, or resume it with --passes " +
                std::to_string(held.first()) + ":END");
  if (held.end() > settings_.passes)
    throw Error("holds " + held.describe() + ", past the " + std::to_string(settings_.passes) + " asked" +
                (mode_ == RenderMode::Path ? " (--spp)" : " (phong and binary take one pass)"));
}

std::optional<AdaptiveSamplerState> Renderer::adaptive_state() const {
  if (!settings_.adaptive) return std::nullopt;
  return driver_ && driver_->adaptive() ? driver_->adaptive()->state() : AdaptiveSamplerState{};
}

RenderState Renderer::state() const {
  RenderState s;
  s.film = film_->state();
  s.adaptive = adaptive_state();
  s.integrator = integrator_->state();
  return s;
}

ImageF Renderer::render(RenderStats* stats, const ProgressCallback& progress, const PassDoneCallback& pass_done,
                        const RenderState* resume) {
  const auto t0 = std::chrono::steady_clock::now();
  begin(resume);
  StopConditions stop;
  stop.passes = settings_.passes;
  stop.first_pass = settings_.first_pass;
  stop.seconds = settings_.time_limit_s;
  run(stop, stats, progress, pass_done);
  ImageF image = finish(stats);
  if (stats)
    stats->render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return image;
}

template <typename F>
auto Renderer::on_device(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const cl::Error& e) {
    throw Error(std::string("render failed on ") + runtime_.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

void Renderer::begin(const RenderState* resume) {
  on_device([&] {
    if (resume) check_state(*resume);
    driver_ = std::make_unique<PassDriver>(*integrator_, *film_, launcher_);
    if (settings_.adaptive) driver_->set_adaptive(settings_.adaptive_options);
    driver_->share_waves(share_);
    if (resume) {
      film_->restore(resume->film);
      if (resume->adaptive) driver_->adaptive()->restore(*resume->adaptive);
      integrator_->restore_state(*film_, resume->integrator, "render state");
    } else {
      film_->clear();
    }
  });
}

void Renderer::run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress,
                   const PassDoneCallback& pass_done) {
  if (!driver_) throw Error("render: run before begin");
  on_device([&] { driver_->run(stop, stats, progress, pass_done); });
}

ImageF Renderer::finish(RenderStats* stats) {
  return on_device([&] {
    ImageF image = film_->mean();
    launcher_.collect(stats);
    integrator_->collect(stats);
    if (stats) stats->film = film_->counts();
    return image;
  });
}

}  // namespace caustica
