// Phong mode: Whitted ray tracing as the coursework defines it. Per hit:
// emission and ambient at once, Blinn-Phong per point light through the
// shadow stage, and a mirror and/or Fresnel-weighted refraction child while
// depth < nbounces. Stages: generate_camera_rays -> { intersect_closest ->
// shade_surface_phong -> intersect_shadow }*, over two ping-pong ray queues
// and one shadow queue; stages the feature set does not need are not
// launched (no shadow stage without lights, one wave without reflection or
// refraction). Area and sphere lights are point-light stand-ins here
// (whitted_point_lights). With --caustics on, a PhotonPass traces photons
// from those lights before each pass and the shade stage gathers them
// (lib/caustics.h); the passes are then averaged like path mode's.
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host/cl/runtime.h"
#include "host/render/lights.h"
#include "host/render/path_lights.h"
#include "host/render/photon_pass.h"

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
    photons_->trace(stats);
  }

 private:
  ShadeParams shade_params() const;

  const SceneFeatures& features_;
  size_t light_count_ = 0;
  size_t ray_capacity_ = 0, shadow_capacity_ = 0;
  cl::Buffer lights_, hits_, shadow_traced_;
  DeviceQueue rays_[2], shadow_;
  StageKernel generate_, intersect_, shade_, shadow_stage_;
  cl::Buffer photon_lights_;
  std::unique_ptr<PhotonPass> photons_;  // --caustics on only
};

float max3(const cs_float4& v) { return std::max(v.x, std::max(v.y, v.z)); }

// IEEE half bits to float, for the texel bound (finite, non-negative texels).
float half_to_float(uint16_t h) {
  const int exponent = (h >> 10) & 0x1F, mantissa = h & 0x3FF;
  if (exponent == 0x1F) return 65504.0f;  // Inf/NaN do not occur in loaded textures; bound them anyway
  if (exponent == 0) return std::ldexp(float(mantissa), -24);
  return std::ldexp(1.0f + float(mantissa) / 1024.0f, exponent - 15);
}

}  // namespace

// The largest sum a phong pass can add to one pixel: per ray, emission plus
// the largest of the background and ambient + every light's Blinn-Phong
// maximum; a ray's children share its weight (mirror r and 1 - r, Fresnel F
// and 1 - F), so the weights of one depth sum to at most 1, and the bound
// is that per-ray maximum times (nbounces + 1).
float phong_pass_bound(const Scene& scene, const std::vector<PointLight>& lights, int max_depth) {
  // Texels of non-negative halves order like their bit patterns.
  float texel_max = 0.0f;
  for (size_t i = 0; i < scene.texels.size(); i += 4)
    for (size_t c = 0; c < 3 && i + c < scene.texels.size(); ++c)
      if (!(scene.texels[i + c] & 0x8000)) texel_max = std::max(texel_max, half_to_float(scene.texels[i + c]));
  for (const Texture& t : scene.textures)
    if (t.kind == TEXTURE_CHECKER) texel_max = std::max(texel_max, std::max(max3(t.color1), max3(t.color2)));
  float emission = 0.0f, local = 0.0f, ambient = 0.0f;
  const glm::vec3 ambient_light = scene.ambient_light.value_or(glm::vec3(1.0f));
  const float ambient_scale = std::max(ambient_light.x, std::max(ambient_light.y, ambient_light.z));
  float light_sum = 0.0f;
  for (const PointLight& l : lights) light_sum += max3(l.intensity);
  for (const Material& m : scene.materials) {
    const float diffuse = std::max(max3(m.diffuse), m.texture >= 0 ? texel_max : 0.0f);
    emission = std::max(emission, max3(m.emission));
    ambient = std::max(ambient, std::abs(m.ka) * ambient_scale * diffuse);
    local = std::max(local, std::abs(m.diffuse.w) * diffuse + std::abs(m.specular.w) * max3(m.specular));
  }
  const float background = std::max(scene.background.x, std::max(scene.background.y, scene.background.z));
  const float per_ray = emission + std::max(background, ambient + light_sum * local);
  return std::max(1.0f, per_ray * float(std::max(0, max_depth) + 1));
}

PhongIntegrator::PhongIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                                 const RenderSettings& settings)
    : Integrator("phong", launcher, scene, settings), features_(scene.features()) {
  auto& ctx = launcher.runtime().context();
  const std::vector<PointLight> lights = whitted_point_lights(scene.scene());
  lights_ = upload_buffer(ctx, lights);
  light_count_ = features_.lights ? lights.size() : 0;
  const int max_depth = features_.secondary_rays() ? std::max(0, scene.scene().nbounces) : 0;
  pass_bound_ = phong_pass_bound(scene.scene(), lights, max_depth);

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
  shadow_traced_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  rays_[0] = DeviceQueue(ctx, path_record_layout(), ray_capacity_);
  // Unused without secondary rays (a one-slot stand-in keeps the binding uniform).
  rays_[1] = DeviceQueue(ctx, path_record_layout(), features_.secondary_rays() ? ray_capacity_ : 1);
  shadow_ = DeviceQueue(ctx, shadow_record_layout(), light_count_ > 0 ? shadow_capacity_ : 1);

  generate_ = StageKernel(program, "generate_camera_rays");
  intersect_ = StageKernel(program, "intersect_closest");
  shade_ = StageKernel(program, "shade_surface_phong");
  shadow_stage_ = StageKernel(program, "intersect_shadow");
  if (settings.caustics) {
    const std::vector<PathLight> photon_lights = point_path_lights(lights);
    if (!photon_lights.empty()) {
      photon_lights_ = upload_buffer(ctx, photon_lights);
      photons_ = std::make_unique<PhotonPass>(launcher, scene, program, photon_lights_,
                                              uint32_t(photon_lights.size()), settings, PhotonGather::SharedRadius);
      // A focused caustic can exceed the direct light's bound by far.
      pass_bound_ *= 1e4f;
    }
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
  DeviceQueue* current = &rays_[0];
  DeviceQueue* next = &rays_[1];
  generate_camera_rays(generate_, *current, first_pixel, pixel_count, stats);

  const ShadeParams params = shade_params();
  if (light_count_ > 0) launcher_.write_count(shadow_traced_, 0, stats);
  uint32_t ray_count = uint32_t(pixel_count);
  for (cl_uint depth = 0; ray_count > 0; ++depth) {
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", *current).arg("hits", hits_).finish();
    launcher_.launch(intersect_, ray_count, stats);

    const bool spawns = depth < params.max_depth;
    if (spawns) launcher_.write_count(next->count(), 0, stats);
    // Ray i's shadow rays occupy slots [i L, (i + 1) L): the count is known.
    const uint32_t shadow_count = uint32_t(ray_count * light_count_);
    if (light_count_ > 0) launcher_.write_count(shadow_.count(), shadow_count, stats);
    KernelArgs shade(shade_);
    scene_.bind_surfaces(shade).arg("lights", lights_).arg("params", params).queue("in", *current).arg("hits", hits_);
    film.bind(shade).queue("next", *next).queue("shadow", shadow_);
    if (photons_) photons_->bind_photon_map(shade);
    shade.finish();
    launcher_.launch(shade_, ray_count, stats);

    if (light_count_ > 0) {
      KernelArgs shadow(shadow_stage_);
      film.bind(scene_.bind_geometry(shadow).queue("shadow", shadow_)).arg("traced", shadow_traced_).finish();
      launcher_.launch(shadow_stage_, shadow_count, stats);
      if (stats) stats->shadow_slots += shadow_count;
    }
    if (!spawns) break;  // the chunk's traced shadow rays are read below
    ray_count = launcher_.read_count(next->count(), stats);
    if (ray_count > ray_capacity_) return false;
    if (stats) stats->secondary_rays += ray_count;
    std::swap(current, next);
  }
  if (light_count_ > 0 && stats) stats->shadow_rays += launcher_.read_count(shadow_traced_, stats);
  return true;
}

std::unique_ptr<Integrator> make_phong_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings) {
  return std::make_unique<PhongIntegrator>(launcher, scene, program, settings);
}

}  // namespace caustica
