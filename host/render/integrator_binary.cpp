// Binary mode: red where the camera ray hits anything, black elsewhere.
// Stages: generate_camera_rays -> intersect_closest -> shade_surface_binary.
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

#include <algorithm>

#include "host/cl/runtime.h"

namespace caustica {
namespace {

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

}  // namespace

BinaryIntegrator::BinaryIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                                   const RenderSettings& settings)
    : launcher_(launcher), scene_(scene), settings_(settings) {
  Runtime& runtime = launcher.runtime();
  chunk_ = std::min(size_t(settings.width) * size_t(settings.height), settings.chunk_pixels);
  rays_ = DeviceQueue(runtime.context(), path_record_layout(), chunk_);
  hits_ = cl::Buffer(runtime.context(), CL_MEM_READ_WRITE, chunk_ * sizeof(Hit));
  generate_ = StageKernel(program, "generate_camera_rays");
  intersect_ = StageKernel(program, "intersect_closest");
  shade_ = StageKernel(program, "shade_surface_binary");
}

bool BinaryIntegrator::trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, RenderStats* stats) {
  CameraGPU camera = camera_for_image(scene_.scene().camera, settings_.width, settings_.height);
  camera.pixel_offset = cl_uint(first_pixel);
  camera.pixel_count = cl_uint(pixel_count);
  KernelArgs(generate_).arg("camera", camera).queue("out", rays_).finish();
  launcher_.launch(generate_, pixel_count, stats);
  launcher_.write_count(rays_.count(), cl_uint(pixel_count), stats);
  if (stats) stats->camera_rays += pixel_count;

  KernelArgs intersect(intersect_);
  scene_.bind_geometry(intersect).ray_view("rays", rays_).arg("hits", hits_).finish();
  launcher_.launch(intersect_, pixel_count, stats);

  KernelArgs shade(shade_);
  film.bind(shade.queue("in", rays_).arg("hits", hits_)).finish();
  launcher_.launch(shade_, pixel_count, stats);
  return true;
}

std::unique_ptr<Integrator> make_binary_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings) {
  return std::make_unique<BinaryIntegrator>(launcher, scene, program, settings);
}

}  // namespace caustica
