// The wavefront driver: uploads a scene once, then runs
//   generate -> { intersect_closest -> shade_surface -> intersect_shadow }*
// over pixel chunks, with the queue counters read back between stages to
// size the next launch. Stages the scene's feature set does not need are not
// launched (no shadow stage without lights, no second wave without
// reflection or refraction).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "host/accel/bvh_wide.h"
#include "host/cl/runtime.h"
#include "host/image/image.h"
#include "host/scene/features.h"
#include "host/scene/scene.h"

namespace caustica {

struct RenderSettings {
  int width = 0;   // image size (already resolved from the camera and CLI)
  int height = 0;
  size_t local_size = 64;        // work-group size of every stage launch
  size_t chunk_pixels = 1 << 19; // pixels per wavefront; bounds queue memory
  float min_weight = 1e-4f;      // secondary rays below this weight are not traced
  // Ray queue capacity = factor x chunk. 2 holds any single wave; deeper
  // Fresnel trees overflow and their chunk is re-rendered in halves.
  float queue_capacity_factor = 2.0f;
};

struct RenderStats {
  double render_ms = 0.0;
  uint64_t camera_rays = 0;
  uint64_t secondary_rays = 0;
  uint64_t shadow_rays = 0;
  int chunk_retries = 0;  // chunks re-rendered in halves after a queue overflow
};

// Kernel-throughput figures for `caustica bench` (medians over repetitions).
struct KernelTimings {
  double primary_ms = 0.0;
  uint64_t primary_rays = 0;
  double shadow_ms = 0.0;
  uint64_t shadow_rays = 0;
};

struct RayQueue;

class WavefrontRenderer {
 public:
  WavefrontRenderer(Runtime& runtime, const Scene& scene, const WideBvh& bvh, const SceneFeatures& features,
                    const cl::Program& program, const RenderSettings& settings);
  ~WavefrontRenderer();

  using Progress = std::function<void(size_t pixels_done, size_t pixels_total)>;
  ImageF render(RenderStats* stats, const Progress& progress = {});

  // Times intersect_closest on the primary rays of the first chunk and
  // intersect_shadow on the shadow rays its hits produce.
  KernelTimings time_kernels(int repetitions);

  // Times `kernel` on an arbitrary ray batch (caustica bench traces host-made
  // rays with the renderer's kernels). The kernel takes
  //   (SCENE_GEOMETRY_PARAMS, const uint* count, const float4* origin,
  //    const float4* dir, T* result)
  // with one result of result_bytes per ray, and must come from a program
  // on this renderer's context. All rays go in one launch with the
  // renderer's local size; the median of `repetitions` launches after one
  // warm-up launch of the same grid (PoCL compiles per launch shape) is
  // returned in ms. The last launch's results are copied to `results`
  // (size() * result_bytes bytes) when it is not null.
  double time_ray_kernel(cl::Kernel& kernel, const std::vector<cs_float4>& origin,
                         const std::vector<cs_float4>& dir, size_t result_bytes, int repetitions,
                         void* results = nullptr);

 private:
  struct Buffers;
  void render_chunk(size_t first_pixel, size_t pixel_count, RenderStats* stats);
  bool run_chunk(size_t first_pixel, size_t pixel_count, RenderStats* stats);  // false on queue overflow
  CameraGPU camera_for_chunk(size_t first_pixel, size_t pixel_count) const;
  void bind_intersect(RayQueue& rays);
  void bind_shade(const ShadeParams& params, RayQueue& in, RayQueue& next);
  void bind_shadow();
  ShadeParams shade_params(cl_uint max_depth) const;
  void launch(cl::Kernel& kernel, size_t count);
  double median_launch_ms(cl::Kernel& kernel, size_t count, int repetitions);  // after a warm-up launch
  uint32_t read_count(const cl::Buffer& counter);
  void write_count(const cl::Buffer& counter, uint32_t value);

  Runtime& runtime_;
  const Scene& scene_;
  SceneFeatures features_;
  RenderSettings settings_;
  std::unique_ptr<Buffers> buffers_;
  cl::Kernel generate_, intersect_, shade_, shadow_;
};

}  // namespace caustica
