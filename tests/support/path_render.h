// Path-mode renders for tests, in process: a scene written from text, one
// render with the film's half buffer kept, and image means with their
// standard errors. The mean of all passes M and of the film's second half B
// differ by E[(M - B)^2] = Var(M) for independent halves, so over n values
// the mean's standard error is sqrt(sum (M - B)^2) / n.
#pragma once

#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include <vector>

#include "host/app/session.h"
#include "host/render/error_estimate.h"
#include "host/render/renderer.h"
#include "tests/support/test_support.h"

namespace caustica::test {

struct PathRender {
  ImageF image, half;  // half: the mean of the film's half buffer
  RenderStats stats;
  std::vector<uint32_t> spp, half_counts;  // per pixel (Film::pixel_spp, half_counts)
  std::vector<uint64_t> pixel_rays;         // per pixel (Film::pixel_rays)
  double estimated_rel_mse = 0.0;           // the film's own estimate (spp >= 2)
};

struct PathRenderOptions {
  CausticsMode caustics = CausticsMode::Auto;
  uint32_t strategy = PATH_STRATEGY_MIS;
  size_t local_size = 64;
  size_t path_slots = 0;  // 0: the integrator's own (RenderSettings::chunk_pixels bounds it)
  bool adaptive = false;  // adaptive sampling (host/render/adaptive_sampling.h); uniform by default here
  uint32_t seed = 0;
  bool aux_passes = false;  // the film's albedo, normal and depth passes (host/render/film.h)
  int width = 0, height = 0;  // 0: the scene camera's
  KernelShape kernel_shape = KernelShape::Auto;  // auto: the device's (paths on a CPU)
  LightSampler light_sampler = LightSampler::Auto;  // auto: the product's default (the tree above 3 lights)
  std::function<void(const Film&)> inspect;  // called with the film after the render
};

inline PathRender render_path(const std::string& scene, int spp, const PathRenderOptions& options = {}) {
  SessionOptions o;
  o.scene_path = scene;
  o.device = device_spec();
  o.mode = RenderMode::Path;
  o.spp = spp;
  o.local_size = options.local_size;
  o.caustics = options.caustics;
  o.aux_passes = options.aux_passes;
  o.width = options.width;
  o.height = options.height;
  o.kernel_shape = options.kernel_shape;
  o.light_sampler = options.light_sampler;
  // At least 2^14 photons a pass by default whatever the image size: 1024
  // on Oclgrind, whose tests render a few hundred pixels.
  if (on_simulator()) o.photons = 1024;
  auto s = prepare_session(o);
  RenderSettings settings = s->settings;
  settings.path_strategy = options.strategy;
  if (options.path_slots) settings.chunk_pixels = options.path_slots;
  settings.half_buffer = spp >= 2;
  settings.adaptive = options.adaptive;
  settings.seed = options.seed;
  Renderer r(*s->runtime, *s->device_scene, s->mode, s->program.program, settings);
  PathRender out;
  out.image = r.render(&out.stats);
  expect_finite_render(out.image, out.stats.film, scene);
  out.spp = r.film().pixel_spp();
  out.half_counts = r.film().half_counts();
  out.pixel_rays = r.film().pixel_rays();
  if (spp >= 2) {
    out.half = r.film().half_mean();
    const ImageF separate = r.film().separate_variance();
    out.estimated_rel_mse = caustica::estimated_rel_mse(out.image, out.half, out.spp, out.half_counts, &separate);
  }
  if (options.inspect) options.inspect(r.film());
  return out;
}

// A render of any mode through the session's own renderer, with the camera
// that made it (tests that find where image positions land in the scene).
struct CameraRender {
  ImageF image;
  CameraGPU camera;
};
struct CameraRenderOptions {
  int spp = 1;
  CausticsMode caustics = CausticsMode::Off;
  int size = 0;  // width and height; 0: the scene's
  uint32_t seed = 0;
};
inline CameraRender render_with_camera(const std::string& scene_path, RenderMode mode,
                                       const CameraRenderOptions& options = {}) {
  SessionOptions o;
  if (options.size > 0) o.width = o.height = options.size;
  o.scene_path = scene_path;
  o.device = device_spec();
  o.mode = mode;
  o.spp = options.spp;
  o.seed = options.seed;
  o.caustics = options.caustics;
  auto s = prepare_session(o);
  RenderStats stats;
  CameraRender r;
  r.image = s->renderer->render(&stats, {}, {});
  expect_finite_render(r.image, stats.film, scene_path);
  r.camera = camera_for_image(s->scene.camera, r.image.width, r.image.height);
  return r;
}

// Mean of channels 0..2 over the pixels where keep(x, y), and its standard error.
struct Mean {
  double mean = 0, se = 0;
  int pixels = 0;
};
template <class Keep>
Mean mean_over(const PathRender& r, Keep keep) {
  Mean m;
  double sum = 0, var = 0;
  for (int y = 0; y < r.image.height; ++y)
    for (int x = 0; x < r.image.width; ++x) {
      if (!keep(x, y)) continue;
      ++m.pixels;
      for (int c = 0; c < 3; ++c) {
        sum += r.image.at(x, y)[c];
        const double d = r.image.at(x, y)[c] - r.half.at(x, y)[c];
        var += d * d;
      }
    }
  m.mean = sum / (3.0 * m.pixels);
  m.se = std::sqrt(var) / (3.0 * m.pixels);
  return m;
}
inline Mean mean_all(const PathRender& r) {
  return mean_over(r, [](int, int) { return true; });
}

}  // namespace caustica::test
