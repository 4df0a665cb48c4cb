#include "host/app/session.h"

#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>
#include <optional>

#include "host/elapsed.h"
#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"
#include "host/render/film.h"
#include "host/lights/light_table.h"
#include "host/scene/load_scene.h"

namespace caustica {

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

const char* bvh_quality_name(BvhBuildOptions::Quality q) {
  switch (q) {
    case BvhBuildOptions::Quality::Fast: return "fast";
    case BvhBuildOptions::Quality::Sah: return "sah";
    case BvhBuildOptions::Quality::Spatial: return "spatial";
  }
  return "unknown";
}

void check_image_size_limits(const std::string& what, long long width, long long height) {
  using namespace limits;
  if (width > kMaxImageSide || height > kMaxImageSide ||
      (width > 0 && height > 0 && uint64_t(width) * uint64_t(height) > kMaxImagePixels))
    throw Error(what + " " + std::to_string(width) + "x" + std::to_string(height) +
                " is over the image limit of " + std::to_string(kMaxImageSide) + " pixels per side and " +
                std::to_string(kMaxImagePixels) + " pixels in all (16384x16384)");
}

void resolve_image_size(const CameraDesc& camera, int width_override, int height_override, int* width, int* height) {
  if (width_override < 0 || height_override < 0) throw Error("--width/--height must be positive");
  check_image_size_limits("--width/--height", width_override, height_override);
  const double aspect = double(camera.width) / double(camera.height);
  auto derived = [](double v) {  // a thin camera can scale one side past any int
    return v > double(limits::kMaxImageSide) ? limits::kMaxImageSide + 1 : std::max(1, int(std::lround(v)));
  };
  if (width_override > 0 && height_override > 0) {
    *width = width_override;
    *height = height_override;
  } else if (width_override > 0) {
    *width = width_override;
    *height = derived(width_override / aspect);
  } else if (height_override > 0) {
    *height = height_override;
    *width = derived(height_override * aspect);
  } else {
    *width = camera.width;
    *height = camera.height;
  }
  check_image_size_limits("image size", *width, *height);
}

namespace {

// The film's buffers (host/render/film.cpp) are the ones the image size
// drives: a 128-bit fixed-point pass and the 128-bit accumulated sums (one
// or two copies), 3 values a pixel, 10 with the aux passes (FilmLayout);
// with the textures, the largest the user controls. They
// are checked against the device before anything is created, so that a
// request too large gives a message saying what and why instead of
// CL_INVALID_BUFFER_SIZE from deep inside the render.
void check_device_memory(const DeviceInfo& device, const RenderSettings& settings, const Scene& scene) {
  const uint64_t pixels = uint64_t(settings.width) * uint64_t(settings.height);
  const FilmLayout layout{pixels, settings.aux_passes, settings.half_buffer || settings.adaptive};
  const uint64_t pass = layout.values() * Film::kAccumulatedValueBytes, accumulated = layout.words() * sizeof(uint64_t);
  const uint64_t texels = uint64_t(scene.texels.size()) * sizeof(uint16_t);
  const std::string size = std::to_string(settings.width) + "x" + std::to_string(settings.height);
  const std::string on = " on " + device.name + " (" + device.platform_name + ")";
  if (device.max_alloc_bytes > 0) {
    const uint64_t largest = std::max(pass, accumulated);
    if (largest > device.max_alloc_bytes)
      throw Error("image size " + size + " needs a film buffer of " + std::to_string(largest >> 20) +
                  " MiB, more than the largest buffer the device allows (" +
                  std::to_string(device.max_alloc_bytes >> 20) + " MiB, CL_DEVICE_MAX_MEM_ALLOC_SIZE)" + on +
                  "; lower --width/--height");
    if (texels > device.max_alloc_bytes)
      throw Error(scene.source_path + ": the textures need " + std::to_string(texels >> 20) +
                  " MiB of texels, more than the largest buffer the device allows (" +
                  std::to_string(device.max_alloc_bytes >> 20) + " MiB, CL_DEVICE_MAX_MEM_ALLOC_SIZE)" + on);
  }
  if (device.global_mem_bytes > 0 && pass + accumulated + texels > device.global_mem_bytes)
    throw Error("image size " + size + " with these textures needs " +
                std::to_string((pass + accumulated + texels) >> 20) + " MiB of film and texels, more than the " +
                std::to_string(device.global_mem_bytes >> 20) + " MiB of device memory (CL_DEVICE_GLOBAL_MEM_SIZE)" +
                on + "; lower --width/--height");
}

bool out_of_device_memory(cl_int err) {
  return err == CL_INVALID_BUFFER_SIZE || err == CL_MEM_OBJECT_ALLOCATION_FAILURE || err == CL_OUT_OF_RESOURCES ||
         err == CL_OUT_OF_HOST_MEMORY;
}

}  // namespace

std::unique_ptr<Session> prepare_session(const SessionOptions& options) {
  auto session = std::make_unique<Session>();
  auto t0 = std::chrono::steady_clock::now();
  LoadOptions load_options;
  load_options.strict = options.strict;
  load_options.gltf_camera = options.gltf_camera;
  session->scene = options.scene ? *options.scene : load_scene(options.scene_path, load_options);
  session->load_ms = ms_since(t0);
  Scene& scene = session->scene;
  if (options.edit_scene) {
    // An edited scene bypassed the loader's checks of its shapes.
    options.edit_scene(scene);
    for (const std::string& m : drop_degenerate_shapes(scene))
      std::fprintf(stderr, "%s: warning: %s\n", scene.source_path.c_str(), m.c_str());
  }
  session->mode = options.mode.value_or(scene.mode);
  const std::string program_file = integrator_program_file(session->mode);
  // Everything the options and the scene decide is checked before any
  // device, kernel or BVH work.
  resolve_image_size(scene.camera, options.width, options.height, &session->settings.width,
                     &session->settings.height);
  if (options.spp < 0) throw Error("--spp must be positive");
  // Every file light has a phong stand-in (LightTypes.HostRegistryMirrorsTheDevices).
  const uint64_t whitted_light_count = scene.lights.size();
  if (session->mode == RenderMode::Phong && whitted_light_count > limits::kMaxPhongLights)
    throw Error(scene.source_path + ": /scene/lightsources: phong mode traces a shadow ray to each of the " +
                std::to_string(whitted_light_count) + " lights from every shading point; its limit is " +
                std::to_string(limits::kMaxPhongLights) + " lights (--mode path samples them instead)");
  // The path tracer hits the lights it samples: their geometry joins the scene.
  if (session->mode == RenderMode::Path) add_light_geometry(scene);

  session->features = analyse_scene(scene, session->mode, options.caustics);
  const bool path = session->mode == RenderMode::Path;
  // The path tracer's light table, built at most once here, for what needs
  // its size: the photon pass and --light-sampler auto.
  std::optional<size_t> path_lights;
  const auto path_light_count = [&] {
    if (!path_lights) path_lights = build_light_table(scene).lights.size();
    return *path_lights;
  };
  // The photon pass needs a light that emits photons: its program and its
  // integrator decide alike (a light whose power overflows is refused here,
  // before anything is built).
  if (session->features.caustics) {
    const bool emitters = path ? path_light_count() > 0 : !phong_photon_lights(scene).empty();
    if (!emitters) {
      session->features.caustics = false;
      session->features.caustics_reason = "no light emits photons";
    }
  }
  // --light-sampler auto: the light tree where the path tracer's table has
  // more than a handful of lights (kLightTreeThreshold, measured).
  if (path) {
    LightSampler sampler = options.light_sampler;
    if (sampler == LightSampler::Auto)
      sampler = path_light_count() > kLightTreeThreshold ? LightSampler::Tree : LightSampler::Power;
    session->settings.light_sampler = sampler;
    session->features.light_tree = sampler != LightSampler::Power;
  }
  session->features.check_numerics = path && options.check_numerics;
  session->features.aux_passes = path && options.aux_passes;
  if (options.edit_features) options.edit_features(session->features);
  // What the program declares, the integrators bind: these settings are the
  // features, never decided apart from them.
  session->settings.check_numerics = session->features.check_numerics;
  session->settings.aux_passes = session->features.aux_passes;
  session->settings.caustics = session->features.caustics;
  session->settings.adaptive = path && options.adaptive;
  session->settings.half_buffer = path && (options.error_estimate || options.adaptive);
  session->settings.caustics_auto = options.caustics == CausticsMode::Auto;
  if (options.photons > 0) session->settings.photons_per_pass = options.photons;
  if (options.caustic_radius > 0.0f) session->settings.caustic_radius = options.caustic_radius;
  const DeviceInfo device = select_device(options.device);
  check_device_memory(device, session->settings, scene);
  session->runtime = Runtime::shared(device, options.profile_stages);
  // The CPU's shape where the device is a CPU (issue 39): whole paths per
  // work-item; the wavefront on GPUs, whose threads want queues of like work.
  session->settings.kernel_shape = options.kernel_shape != KernelShape::Auto ? options.kernel_shape
                                   : device.type == "cpu"                    ? KernelShape::Paths
                                                                             : KernelShape::Wavefront;
  session->runtime->set_cache_enabled(options.use_kernel_cache);
  session->program = session->runtime->build_file(program_file, session->features.build_options());

  BvhBuildOptions bvh_options;
  bvh_options.quality = options.bvh_quality;
  session->bvh = build_bvh(scene, bvh_options);
  session->wide = collapse_bvh(session->bvh, scene);

  session->settings.local_size = options.local_size;
  // A time limit or a target error alone leaves the sample count open.
  const int default_spp =
      options.time_limit_s > 0.0 || options.open_ended ? std::numeric_limits<int>::max() : kDefaultPathSpp;
  // Phong is one deterministic pass, unless its photon pass needs many.
  const bool progressive = path || session->features.caustics;
  session->settings.passes = progressive ? (options.spp > 0 ? options.spp : default_spp) : 1;
  session->settings.time_limit_s = progressive ? options.time_limit_s : 0.0;
  session->settings.first_pass = progressive ? options.first_pass : 0;
  session->settings.seed = options.seed;
  session->settings.sampler = options.independent_samples ? SAMPLER_INDEPENDENT : SAMPLER_SOBOL_BURLEY;
  t0 = std::chrono::steady_clock::now();
  try {
    session->device_scene =
        std::make_unique<DeviceScene>(session->runtime->context(), scene, session->wide, session->features);
    session->renderer = std::make_unique<Renderer>(*session->runtime, *session->device_scene, session->mode,
                                                   session->program.program, session->settings);
  } catch (const cl::Error& e) {
    // What check_device_memory cannot foresee (queues, geometry): still one
    // line saying what was being allocated, and on which device.
    if (!out_of_device_memory(e.err())) throw;
    throw Error(scene.source_path + ": the device " + device.name + " cannot hold this render's buffers (" +
                std::to_string(session->settings.width) + "x" + std::to_string(session->settings.height) + ", " +
                std::to_string(scene.triangles.size()) + " triangles, " + std::to_string(scene.light_count()) +
                " lights): " + e.what() + " failed with " + cl_error_name(e.err()) + " (largest buffer " +
                std::to_string(device.max_alloc_bytes >> 20) + " MiB, device memory " +
                std::to_string(device.global_mem_bytes >> 20) + " MiB)");
  }
  session->upload_ms = ms_since(t0);
  return session;
}

}  // namespace caustica
