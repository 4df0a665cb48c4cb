#include "host/render/integrator.h"

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/render/device_scene.h"
#include "host/render/kernel_args.h"

namespace caustica {

void StageLauncher::launch(StageKernel& stage, size_t count, RenderStats* stats) {
  if (count == 0) return;
  cl::Event event;
  runtime_.queue().enqueueNDRangeKernel(stage.kernel, cl::NullRange, cl::NDRange(round_up(count, local_size_)),
                                        cl::NDRange(local_size_), nullptr,
                                        runtime_.profiling() ? &event : nullptr);
  if (runtime_.profiling()) events_.emplace_back(stage.name, event);
  if (stats) ++stats->launches;
}

void StageLauncher::collect(RenderStats* stats) {
  if (events_.empty()) return;
  runtime_.queue().finish();
  for (auto& [name, event] : events_) {
    const cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    if (stats) stats->stage_ms[name] += double(end - start) * 1e-6;
  }
  events_.clear();
}

uint32_t StageLauncher::read_count(const cl::Buffer& counter, RenderStats* stats) {
  cl_uint value = 0;
  runtime_.queue().enqueueReadBuffer(counter, CL_TRUE, 0, sizeof value, &value);
  if (stats) ++stats->blocking_transfers;
  return value;
}

void StageLauncher::write_count(const cl::Buffer& counter, uint32_t value, RenderStats* stats) {
  const cl_uint v = value;
  runtime_.queue().enqueueWriteBuffer(counter, CL_TRUE, 0, sizeof v, &v);
  if (stats) ++stats->blocking_transfers;
}

void StageLauncher::read_async(const cl::Buffer& buffer, size_t bytes, void* destination, cl::Event* done,
                               RenderStats* stats) {
  runtime_.queue().enqueueReadBuffer(buffer, CL_FALSE, 0, bytes, destination, nullptr, done);
  if (stats) ++stats->count_reads;
}

CameraGPU Integrator::chunk_camera(size_t first_pixel, size_t pixel_count) const {
  CameraGPU camera = camera_for_image(scene_.scene().camera, settings_.width, settings_.height);
  camera.pixel_offset = cl_uint(first_pixel);
  camera.pixel_count = cl_uint(pixel_count);
  return camera;
}

void Integrator::generate_camera_rays(StageKernel& generate, const DeviceQueue& rays, const cl::Buffer& count,
                                      const cl::Buffer& next_count, size_t first_pixel, size_t pixel_count,
                                      RenderStats* stats) {
  KernelArgs(generate)
      .arg("camera", chunk_camera(first_pixel, pixel_count))
      .queue("out", rays, count)
      .arg("next_count", next_count)
      .finish();
  launcher_.launch(generate, pixel_count, stats);
  if (stats) stats->camera_rays += pixel_count;
}

KernelShape parse_kernel_shape(const std::string& name) {
  if (name == "auto") return KernelShape::Auto;
  if (name == "wavefront") return KernelShape::Wavefront;
  if (name == "paths") return KernelShape::Paths;
  throw Error("--kernel-shape: expected auto, wavefront or paths, got '" + name + "'");
}

const char* kernel_shape_name(KernelShape shape) {
  switch (shape) {
    case KernelShape::Auto: return "auto";
    case KernelShape::Wavefront: return "wavefront";
    case KernelShape::Paths: return "paths";
  }
  return "?";
}

std::string integrator_program_file(RenderMode mode) {
  switch (mode) {
    case RenderMode::Binary: return "integrator_binary.cl";
    case RenderMode::Phong: return "integrator_phong.cl";
    case RenderMode::Path: return "integrator_path.cl";
  }
  throw Error("unknown render mode");
}

std::unique_ptr<Integrator> make_integrator(RenderMode mode, StageLauncher& launcher, const DeviceScene& scene,
                                            const cl::Program& program, const RenderSettings& settings) {
  switch (mode) {
    case RenderMode::Binary: return make_binary_integrator(launcher, scene, program, settings);
    case RenderMode::Phong: return make_phong_integrator(launcher, scene, program, settings);
    case RenderMode::Path: return make_path_integrator(launcher, scene, program, settings);
  }
  throw Error("unknown render mode");
}

}  // namespace caustica
