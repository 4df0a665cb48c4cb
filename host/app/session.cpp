#include "host/app/session.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "host/error.h"
#include "host/render/path_lights.h"
#include "host/scene/load_scene.h"

namespace caustica {
namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

std::optional<RenderMode> parse_render_mode(const std::string& name) {
  if (name.empty()) return std::nullopt;
  if (name == "binary") return RenderMode::Binary;
  if (name == "phong") return RenderMode::Phong;
  if (name == "path" || name == "pathtracer" || name == "pathtracing") return RenderMode::Path;
  throw Error("--mode " + name + ": expected binary, phong or path");
}

BvhBuildOptions::Quality parse_bvh_quality(const std::string& name) {
  if (name == "fast") return BvhBuildOptions::Quality::Fast;
  if (name == "sah") return BvhBuildOptions::Quality::Sah;
  if (name == "spatial") return BvhBuildOptions::Quality::Spatial;
  throw Error("--bvh " + name + ": expected fast, sah or spatial");
}

void resolve_image_size(const CameraDesc& camera, int width_override, int height_override, int* width, int* height) {
  if (width_override < 0 || height_override < 0) throw Error("--width/--height must be positive");
  const double aspect = double(camera.width) / double(camera.height);
  if (width_override > 0 && height_override > 0) {
    *width = width_override;
    *height = height_override;
  } else if (width_override > 0) {
    *width = width_override;
    *height = std::max(1, int(std::lround(width_override / aspect)));
  } else if (height_override > 0) {
    *height = height_override;
    *width = std::max(1, int(std::lround(height_override * aspect)));
  } else {
    *width = camera.width;
    *height = camera.height;
  }
  if (double(*width) * double(*height) > 1.0e9) throw Error("image size " + std::to_string(*width) + "x" +
                                                            std::to_string(*height) + " is too large");
}

std::unique_ptr<Session> prepare_session(const SessionOptions& options) {
  auto session = std::make_unique<Session>();
  auto t0 = std::chrono::steady_clock::now();
  LoadOptions load_options;
  load_options.strict = options.strict;
  session->scene = load_scene(options.scene_path, load_options);
  session->load_ms = ms_since(t0);
  Scene& scene = session->scene;
  if (options.edit_scene) options.edit_scene(scene);
  session->mode = options.mode.value_or(scene.mode);
  const std::string program_file = integrator_program_file(session->mode);
  // The path tracer hits the lights it samples: their geometry joins the scene.
  if (session->mode == RenderMode::Path) add_light_geometry(scene);

  session->features = analyse_scene(scene, session->mode, options.caustics);
  session->runtime = std::make_unique<Runtime>(select_device(options.device), options.profile_stages);
  session->runtime->set_cache_enabled(options.use_kernel_cache);
  session->program = session->runtime->build_file(program_file, session->features.build_options());

  BvhBuildOptions bvh_options;
  bvh_options.quality = options.bvh_quality;
  session->bvh = build_bvh(scene, bvh_options);
  session->wide = collapse_bvh(session->bvh, scene);

  resolve_image_size(scene.camera, options.width, options.height, &session->settings.width,
                     &session->settings.height);
  session->settings.local_size = options.local_size;
  if (options.spp < 0) throw Error("--spp must be positive");
  const bool path = session->mode == RenderMode::Path;
  // A time limit or a target error alone leaves the sample count open.
  const int default_spp =
      options.time_limit_s > 0.0 || options.open_ended ? std::numeric_limits<int>::max() : kDefaultPathSpp;
  // Phong is one deterministic pass, unless its photon pass needs many.
  const bool progressive = path || session->features.caustics;
  session->settings.passes = progressive ? (options.spp > 0 ? options.spp : default_spp) : 1;
  session->settings.time_limit_s = progressive ? options.time_limit_s : 0.0;
  session->settings.seed = options.seed;
  session->settings.half_buffer = path && options.error_estimate;
  session->settings.caustics = session->features.caustics;
  if (options.photons > 0) session->settings.photons_per_pass = options.photons;
  if (options.caustic_radius > 0.0f) session->settings.caustic_radius = options.caustic_radius;
  session->settings.sampler = options.independent_samples ? SAMPLER_INDEPENDENT : SAMPLER_SOBOL_BURLEY;
  t0 = std::chrono::steady_clock::now();
  session->device_scene =
      std::make_unique<DeviceScene>(session->runtime->context(), scene, session->wide, session->features);
  session->renderer = std::make_unique<Renderer>(*session->runtime, *session->device_scene, session->mode,
                                                 session->program.program, session->settings);
  session->upload_ms = ms_since(t0);
  return session;
}

}  // namespace caustica
