// Path mode: unidirectional path tracing with next-event estimation and
// BSDF sampling combined by multiple importance sampling (power heuristic),
// Russian roulette, Sobol-Burley samples. Stages: generate_camera_samples ->
// { intersect_closest -> shade_surface_path -> intersect_shadow }*, over two
// ping-pong path queues (each path pushes at most one continuation, so a
// queue never holds more than the chunk) and one addressed shadow slot per
// path. Every pass is one sample per pixel; the film averages the passes.
// With caustics, a PhotonPass traces photons before each pass's chunks and
// gathers them after (host/render/photon_pass.h).
#include <algorithm>

#include "host/cl/runtime.h"
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"
#include "host/render/path_lights.h"
#include "host/render/photon_pass.h"

namespace caustica {
namespace {

// Owns its light table (PathLight and the per-primitive light indices), two
// path queues and the shadow slots, all sized for one chunk.
class PathIntegrator final : public Integrator {
  StageKernel generate_, intersect_, shade_, shadow_stage_;
  size_t light_count_ = 0;
  cl::Buffer lights_, light_of_sphere_, light_of_cylinder_, light_of_triangle_, hits_, shadow_traced_;
  DeviceQueue rays_[2], shadow_;
  std::unique_ptr<PhotonPass> photons_;  // only with the caustics feature
  cl::Buffer numerics_;                   // only with --check-numerics

 public:
  PathIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                 const RenderSettings& settings);
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, RenderStats* stats) override;
  void begin_pass(Film& film, RenderStats* stats) override {
    if (numerics_() && film.passes() == 0)
      launcher_.runtime().fill(numerics_, cl_ulong(0), 0, NUMERICS_COUNTERS * sizeof(cl_ulong));
    if (!photons_) return;
    if (film.passes() == 0) photons_->clear();
    film.set_separate_estimate(photons_.get());
    photons_->trace(uint32_t(film.passes()), stats);
  }
  void end_pass(Film& film, RenderStats* stats) override {
    if (photons_) photons_->gather(uint32_t(film.passes()), stats);
  }
  void collect(RenderStats* stats) override {
    if (!numerics_() || !stats) return;
    stats->numerics.assign(NUMERICS_COUNTERS, 0);
    launcher_.runtime().queue().enqueueReadBuffer(numerics_, CL_TRUE, 0, NUMERICS_COUNTERS * sizeof(cl_ulong),
                                                  stats->numerics.data());
  }
};

PathIntegrator::PathIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                               const RenderSettings& settings)
    : Integrator("path", launcher, scene, settings),
      generate_(program, "generate_camera_samples"),
      intersect_(program, "intersect_closest"),
      shade_(program, "shade_surface_path"),
      shadow_stage_(program, "intersect_shadow") {
  auto& ctx = launcher.runtime().context();
  const PathLightTable table = build_path_lights(scene.scene());
  light_count_ = table.lights.size();
  lights_ = upload_buffer(ctx, table.lights);
  light_of_sphere_ = upload_buffer(ctx, table.light_of_sphere);
  light_of_cylinder_ = upload_buffer(ctx, table.light_of_cylinder);
  light_of_triangle_ = upload_buffer(ctx, table.light_of_triangle);
  chunk_pixels_ = std::min(size_t(settings.width) * size_t(settings.height), settings.chunk_pixels);
  // One path's sample can carry far more than the scene's radiance
  // (throughput / pdf); the bound only picks the fixed-point scale, and
  // anything beyond 2^56 / scale is clamped and counted.
  const glm::vec3 bg = scene.scene().background;
  pass_bound_ = 1e6f * std::max(1.0f, std::max(table.max_radiance, std::max(bg.x, std::max(bg.y, bg.z))));
  for (DeviceQueue& q : rays_) q = DeviceQueue(ctx, path_record_layout(), chunk_pixels_);
  shadow_ = DeviceQueue(ctx, shadow_record_layout(), chunk_pixels_);
  hits_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, chunk_pixels_ * sizeof(Hit));
  shadow_traced_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  if (settings.check_numerics) numerics_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, NUMERICS_COUNTERS * sizeof(cl_ulong));
  if (settings.caustics && light_count_ > 0)
    photons_ = std::make_unique<PhotonPass>(launcher, scene, program, lights_, uint32_t(light_count_), settings);
}

bool PathIntegrator::trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, RenderStats* stats) {
  const Scene& scene = scene_.scene();
  PathParams params{};
  params.background = to_float4(scene.background);
  params.light_count = cl_uint(light_count_);
  params.max_depth = cl_uint(std::max(0, scene.nbounces));
  params.ray_capacity = cl_uint(chunk_pixels_);
  params.sample_index = cl_uint(film.passes());
  params.seed = settings_.seed;
  params.strategy = settings_.path_strategy;
  params.rr_depth = 3;
  params.sampler = settings_.sampler;

  DeviceQueue* current = &rays_[0];
  DeviceQueue* next = &rays_[1];
  KernelArgs(generate_)
      .arg("camera", chunk_camera(first_pixel, pixel_count))
      .arg("params", params)
      .queue("out", *current)
      .finish();
  launcher_.launch(generate_, pixel_count, stats);
  launcher_.write_count(current->count(), cl_uint(pixel_count), stats);
  launcher_.write_count(shadow_traced_, 0, stats);
  if (stats) stats->camera_rays += pixel_count;

  for (uint32_t ray_count = uint32_t(pixel_count); ray_count > 0;) {
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", *current).arg("hits", hits_).finish();
    launcher_.launch(intersect_, ray_count, stats);

    launcher_.write_count(next->count(), 0, stats);
    launcher_.write_count(shadow_.count(), ray_count, stats);  // slot i: path i's shadow ray
    KernelArgs shade(shade_);
    scene_.bind_surfaces(shade)
        .arg("lights", lights_)
        .arg("light_of_sphere", light_of_sphere_)
        .arg("light_of_cylinder", light_of_cylinder_)
        .arg("light_of_triangle", light_of_triangle_)
        .arg("params", params)
        .queue("in", *current)
        .arg("hits", hits_);
    film.bind(shade).queue("next", *next).queue("shadow", shadow_);
    if (photons_) photons_->bind_photon_map(photons_->bind_visible_points(shade), uint32_t(film.passes()));
    if (numerics_()) shade.arg("numerics", numerics_);
    shade.finish();
    launcher_.launch(shade_, ray_count, stats);

    if (light_count_ > 0 && settings_.path_strategy != PATH_STRATEGY_BSDF) {
      KernelArgs shadow(shadow_stage_);
      film.bind(scene_.bind_geometry(shadow).queue("shadow", shadow_)).arg("traced", shadow_traced_).finish();
      launcher_.launch(shadow_stage_, ray_count, stats);
    }
    ray_count = launcher_.read_count(next->count(), stats);
    if (ray_count > chunk_pixels_) return false;  // cannot happen: one continuation per path at most
    if (stats) stats->secondary_rays += ray_count;
    std::swap(current, next);
  }
  if (stats) stats->shadow_rays += launcher_.read_count(shadow_traced_, stats);
  return true;
}

}  // namespace

std::unique_ptr<Integrator> make_path_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings) {
  return std::make_unique<PathIntegrator>(launcher, scene, program, settings);
}

}  // namespace caustica
