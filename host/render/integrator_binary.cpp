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
                   const RenderSettings& settings)
      : Integrator("binary", launcher, scene, settings),
        generate_(program, "generate_camera_rays"),
        intersect_(program, "intersect_closest"),
        shade_(program, "shade_surface_binary") {
    auto& context = launcher.runtime().context();
    chunk_pixels_ = std::min(size_t(settings.width) * size_t(settings.height), settings.chunk_pixels);
    rays_ = DeviceQueue(context, path_record_layout(), chunk_pixels_);
    hits_ = cl::Buffer(context, CL_MEM_READ_WRITE, chunk_pixels_ * sizeof(Hit));
    unused_count_ = cl::Buffer(context, CL_MEM_READ_WRITE, sizeof(cl_uint));
  }
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats) override;

 private:
  StageKernel generate_, intersect_, shade_;
  DeviceQueue rays_;
  cl::Buffer hits_, unused_count_;  // generate_camera_rays zeroes a next queue's count; binary has none
};

}  // namespace

bool BinaryIntegrator::trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int /*passes: always 1*/,
                                   RenderStats* stats) {
  generate_camera_rays(generate_, rays_, rays_.count(), unused_count_, first_pixel, pixel_count, stats);

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
