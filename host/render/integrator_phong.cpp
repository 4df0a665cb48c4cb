// Phong mode: Whitted ray tracing as the coursework defines it. Per hit:
// emission and ambient at once, Blinn-Phong per point light through the
// shadow stage, and a mirror and/or Fresnel-weighted refraction child while
// depth < nbounces. Stages: generate_camera_rays -> { intersect_closest ->
// shade_surface_phong -> intersect_shadow }*, over two ping-pong ray queues
// and one shadow queue; stages the feature set does not need are not
// launched (no shadow stage without lights, one wave without reflection or
// refraction). Area and sphere lights are point-light stand-ins here
// (whitted_lights). With --caustics on, a PhotonPass traces photons
// from those lights and from the environment (phong_photon_lights) before
// each pass and the shade stage gathers them (lib/caustics.h); the passes
// are then averaged like path mode's. The environment is otherwise only
// the background at misses, so its photons' caustics are light phong did
// not have (docs/environment.md, "Phong").
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/lights/light_table.h"
#include "host/render/photon_pass.h"
#include "host/render/state_bytes.h"
#include "host/render/wave_loop.h"

namespace caustica {
namespace {

// Owns the point-light stand-ins, two ray queues (a wave may double) and
// the shadow slots (lights per ray), sized for one chunk.
class PhongIntegrator final : public Integrator {
 public:
  PhongIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                  const RenderSettings& settings);
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats) override;
  void begin_pass(Film& film, RenderStats* stats) override {
    if (!photons_) return;
    if (film.passes() == 0) photons_->clear();
    // keyed by the absolute pass: ranks trace interleaved passes
    photons_->trace_map(uint32_t(film.wave_first_pass()), stats);
  }
  // --caustics on: the photon pass's maps and radius schedule (render_state.h).
  std::string state() const override {
    if (!photons_) return {};
    StateWriter out;
    photons_->save(out);
    return std::move(out.bytes());
  }
  void restore_state(Film& film, const std::string& bytes, const std::string& what) override {
    if (!photons_) return Integrator::restore_state(film, bytes, what);
    if (bytes.empty()) throw Error(what + ": no photon pass state for a render with the photon pass");
    StateReader in(bytes, 0, bytes.size(), what);
    photons_->load(in);
    if (!in.done()) throw Error(what + ": bytes after the photon pass's state");
  }

 private:
  ShadeParams shade_params() const;

  const SceneFeatures& features_;
  size_t light_count_ = 0;
  size_t ray_capacity_ = 0, shadow_capacity_ = 0;
  cl::Buffer lights_, hits_;
  DeviceQueue rays_[2], shadow_;
  // The bounce loop and its counters (host/render/wave_loop.h): extra
  // counter 0 counts the rays intersect_closest traced, 1 the shadow rays.
  enum { kClosestRays = 0, kShadowRays = 1 };
  std::unique_ptr<WaveLoop> loop_;
  cl_uint closest_rays_seen_ = 0, shadow_rays_seen_ = 0;  // the counters after the latest chunk
  StageKernel generate_, intersect_, shade_, shadow_stage_;
  DeviceLights photon_lights_;
  std::unique_ptr<PhotonPass> photons_;  // --caustics on only
};

}  // namespace

PhongIntegrator::PhongIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                                 const RenderSettings& settings)
    : Integrator("phong", launcher, scene, settings), features_(scene.features()) {
  auto& ctx = launcher.runtime().context();
  const std::vector<Light> lights = whitted_lights(scene.scene());
  lights_ = upload_buffer(ctx, lights);
  light_count_ = features_.lights ? lights.size() : 0;

  const size_t pixels = size_t(settings.width) * size_t(settings.height);
  // Queue memory grows with the chunk and the number of lights; keep the
  // shadow queue within ~2^21 entries.
  size_t chunk = std::min(pixels, settings.chunk_pixels);
  if (light_count_ > 0) chunk = std::min(chunk, std::max<size_t>(4096, (size_t(1) << 21) / light_count_));
  chunk_pixels_ = chunk;
  // A wave can at most double (one reflection + one refraction child per ray).
  ray_capacity_ = features_.secondary_rays() ? std::max(chunk, size_t(double(chunk) * settings.queue_capacity_factor))
                                             : chunk;
  shadow_capacity_ = std::max<size_t>(1, ray_capacity_ * light_count_);
  hits_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, ray_capacity_ * sizeof(Hit));
  loop_ = std::make_unique<WaveLoop>(launcher, std::vector<int>{1, 1});
  rays_[0] = DeviceQueue(ctx, path_record_layout(), ray_capacity_);
  // Unused without secondary rays (a one-slot stand-in keeps the binding uniform).
  rays_[1] = DeviceQueue(ctx, path_record_layout(), features_.secondary_rays() ? ray_capacity_ : 1);
  shadow_ = DeviceQueue(ctx, shadow_record_layout(), light_count_ > 0 ? shadow_capacity_ : 1);

  generate_ = StageKernel(program, "generate_camera_rays");
  intersect_ = StageKernel(program, "intersect_closest");
  shade_ = StageKernel(program, "shade_surface_phong");
  shadow_stage_ = StageKernel(program, "intersect_shadow");
  if (settings.caustics) {
    // The program declares the photon map's parameters: without a pass to
    // bind them, no stage could launch (prepare_session turns the pass off
    // first for a scene without emitters).
    const std::vector<Light> photon_lights = phong_photon_lights(scene.scene());
    if (photon_lights.empty()) throw Error("phong: the photon pass needs a light that emits photons");
    photon_lights_ = DeviceLights(ctx, photon_lights);
    photons_ = std::make_unique<PhotonPass>(launcher, scene, program, photon_lights_, settings,
                                            PhotonGather::SharedRadius);
  }
}

ShadeParams PhongIntegrator::shade_params() const {
  const Scene& scene = scene_.scene();
  ShadeParams params{};
  params.background = to_float4(scene.background);
  params.ambient_light = to_float4(scene.ambient_light.value_or(glm::vec3(1.0f)));
  params.light_count = cl_uint(light_count_);
  params.max_depth = features_.secondary_rays() ? cl_uint(std::max(0, scene.nbounces)) : 0;
  params.ray_capacity = cl_uint(ray_capacity_);
  params.min_weight = settings_.min_weight;
  return params;
}

bool PhongIntegrator::trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int /*passes: always 1*/,
                                   RenderStats* stats) {
  generate_camera_rays(generate_, rays_[0], loop_->traced_count(0), loop_->pushed_count(0), first_pixel,
                       pixel_count, stats);
  const ShadeParams params = shade_params();
  auto enqueue = [&](uint32_t j, size_t decided_bound) {
    // Before the first count read decides (iterations up to kCountLag), a
    // ray's children can double the queue each iteration.
    const size_t bound =
        j <= uint32_t(WaveLoop::kCountLag) ? std::min(ray_capacity_, pixel_count << j) : decided_bound;
    const DeviceQueue& current = rays_[j % 2];
    const DeviceQueue& next = rays_[(j + 1) % 2];
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", current, loop_->traced_count(j)).arg("hits", hits_).finish();
    launcher_.launch(intersect_, bound, stats);

    KernelArgs shade(shade_);
    scene_.bind_surfaces(shade)
        .arg("lights", lights_)
        .arg("params", params)
        .queue("in", current, loop_->traced_count(j))
        .arg("hits", hits_);
    film.bind(shade)
        .queue("next", next, loop_->pushed_count(j))
        .arg("cleared_count", loop_->cleared_count(j))
        .queue("shadow", shadow_)
        .arg("rays_traced", loop_->extra(kClosestRays));
    if (photons_) photons_->bind_photon_map(shade);
    shade.finish();
    launcher_.launch(shade_, bound, stats);

    if (light_count_ > 0) {  // ray i's shadow rays occupy slots [i L, (i + 1) L); the shade stage set the count
      KernelArgs shadow(shadow_stage_);
      film.bind(scene_.bind_geometry(shadow).queue("shadow", shadow_)).arg("traced", loop_->extra(kShadowRays)).finish();
      launcher_.launch(shadow_stage_, bound * light_count_, stats);
    }
  };
  // A ray spawns two children at most (mirror and refraction), so the
  // count kCountLag iterations on is at most 2^kCountLag times the latest
  // one read. Past the capacity the queue dropped rays: trace again.
  auto decide = [&](const WaveLoop::Counters& after, uint32_t seen) -> size_t {
    const cl_uint next = after.queue_count(seen + 1);
    if (next > ray_capacity_) return WaveLoop::kOverflow;
    if (next == 0) return WaveLoop::kStop;
    return std::min(ray_capacity_, size_t(next) << WaveLoop::kCountLag);
  };
  // Depth 0 to nbounces: the last iteration's shade stage spawns nothing.
  const uint32_t iterations = uint32_t(std::max(0, scene_.scene().nbounces)) + 1;
  if (!loop_->run(pixel_count, iterations, enqueue, decide, stats)) return false;
  // The counters run over the render (modulo 2^32).
  const cl_uint closest = loop_->last().extra(kClosestRays) - closest_rays_seen_;
  const cl_uint shadow = loop_->last().extra(kShadowRays) - shadow_rays_seen_;
  closest_rays_seen_ += closest;
  shadow_rays_seen_ += shadow;
  if (stats) {
    stats->secondary_rays += closest - std::min<uint64_t>(closest, pixel_count);
    stats->shadow_rays += shadow;
    stats->shadow_slots += uint64_t(closest) * light_count_;
  }
  return true;
}

std::unique_ptr<Integrator> make_phong_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings) {
  return std::make_unique<PhongIntegrator>(launcher, scene, program, settings);
}

}  // namespace caustica
