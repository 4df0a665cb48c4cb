// Phong mode: Whitted ray tracing as the coursework defines it. Per hit:
// emission and ambient at once, Blinn-Phong per point light through the
// shadow stage, and a mirror and/or Fresnel-weighted refraction child while
// depth < nbounces. Stages: generate_camera_rays -> { intersect_closest ->
// shade_surface_phong -> intersect_shadow }*, over two ping-pong ray queues
// and one shadow queue; stages the feature set does not need are not
// launched (no shadow stage without lights, one wave without reflection or
// refraction). Area and sphere lights are point-light stand-ins here
// (whitted_point_lights).
#pragma once

#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

namespace caustica {

class PhongIntegrator final : public Integrator {
 public:
  PhongIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                  const RenderSettings& settings);
  const char* name() const override { return "phong"; }
  size_t chunk_pixels() const override { return chunk_; }
  float pass_bound() const override { return pass_bound_; }
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, RenderStats* stats) override;

 private:
  ShadeParams shade_params() const;

  StageLauncher& launcher_;
  const DeviceScene& scene_;
  const SceneFeatures& features_;
  RenderSettings settings_;
  size_t light_count_ = 0;
  size_t chunk_ = 0, ray_capacity_ = 0, shadow_capacity_ = 0;
  float pass_bound_ = 1.0f;
  cl::Buffer lights_, hits_, shadow_traced_;
  DeviceQueue rays_[2], shadow_;
  StageKernel generate_, intersect_, shade_, shadow_stage_;
};

// The largest sum a phong pass can add to one pixel: per ray, emission plus
// the largest of the background and ambient + every light's Blinn-Phong
// maximum; a ray's children share its weight (mirror r and 1 - r, Fresnel F
// and 1 - F), so the weights of one depth sum to at most 1, and the bound
// is that per-ray maximum times (nbounces + 1).
float phong_pass_bound(const Scene& scene, const std::vector<PointLight>& lights, int max_depth);

}  // namespace caustica
