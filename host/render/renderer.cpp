#include "host/render/renderer.h"

#include <chrono>

#include "host/cl/runtime.h"
#include "host/error.h"

namespace caustica {

Renderer::Renderer(Runtime& runtime, const DeviceScene& scene, RenderMode mode, const cl::Program& program,
                   const RenderSettings& settings)
    : runtime_(runtime), settings_(settings), launcher_(runtime, settings.local_size) {
  if (settings.width <= 0 || settings.height <= 0) throw Error("render: image size must be positive");
  if (settings.passes <= 0) throw Error("render: the number of passes must be positive");
  try {
    integrator_ = make_integrator(mode, launcher_, scene, program, settings);
    FilmOptions film;
    film.width = settings.width;
    film.height = settings.height;
    film.half_buffer = settings.half_buffer || settings.adaptive;
    film.pass_bound = integrator_->pass_bound();
    film_ = std::make_unique<Film>(runtime, program, film);
  } catch (const cl::Error& e) {
    throw Error(std::string("cannot set up the renderer on ") + runtime.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

ImageF Renderer::render(RenderStats* stats, const ProgressCallback& progress, const PassDoneCallback& pass_done) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    film_->clear();
    StopConditions stop;
    stop.passes = settings_.passes;
    stop.seconds = settings_.time_limit_s;
    PassDriver driver(*integrator_, *film_, launcher_);
    if (settings_.adaptive) driver.set_adaptive(settings_.adaptive_options);
    driver.run(stop, stats, progress, pass_done);
    ImageF image = film_->mean();
    launcher_.collect(stats);
    integrator_->collect(stats);
    if (stats) {
      stats->film = film_->counts();
      stats->render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    return image;
  } catch (const cl::Error& e) {
    throw Error(std::string("render failed on ") + runtime_.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

}  // namespace caustica
