// One render of a scene in one mode: the device scene, the mode's integrator,
// a film and the pass driver, put together. What `caustica render`, the tests
// and the bench's render timing call.
#pragma once

#include <memory>

#include "host/render/device_scene.h"
#include "host/render/film.h"
#include "host/render/integrator.h"
#include "host/render/pass_driver.h"

namespace caustica {

class Renderer {
 public:
  Renderer(Runtime& runtime, const DeviceScene& scene, RenderMode mode, const cl::Program& program,
           const RenderSettings& settings);

  // Clears the film, renders settings.passes passes (or until
  // settings.time_limit_s), returns the mean.
  ImageF render(RenderStats* stats, const ProgressCallback& progress = {}, const PassDoneCallback& pass_done = {});

  Integrator& integrator() { return *integrator_; }
  Film& film() { return *film_; }
  const RenderSettings& settings() const { return settings_; }

 private:
  Runtime& runtime_;
  RenderSettings settings_;
  StageLauncher launcher_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<Film> film_;
};

}  // namespace caustica
