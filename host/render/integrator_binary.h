// Binary mode: red where the camera ray hits anything, black elsewhere.
// Stages: generate_camera_rays -> intersect_closest -> shade_surface_binary.
#pragma once

#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

namespace caustica {

class BinaryIntegrator final : public Integrator {
 public:
  BinaryIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                   const RenderSettings& settings);
  const char* name() const override { return "binary"; }
  size_t chunk_pixels() const override { return chunk_; }
  float pass_bound() const override { return 1.0f; }
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, RenderStats* stats) override;

 private:
  StageLauncher& launcher_;
  const DeviceScene& scene_;
  RenderSettings settings_;
  size_t chunk_ = 0;
  DeviceQueue rays_;
  cl::Buffer hits_;
  StageKernel generate_, intersect_, shade_;
};

}  // namespace caustica
