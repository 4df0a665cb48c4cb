// Everything one render needs, prepared in order with each step timed:
// load scene -> analyse features -> pick device -> build (or load cached)
// kernels -> build BVH -> upload. Shared by `render` and `bench`.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "host/cl/runtime.h"
#include "host/render/device_scene.h"
#include "host/render/renderer.h"
#include "host/scene/features.h"
#include "host/scene/scene.h"

namespace caustica {

// Display gamma of 8-bit outputs by default. Calibrated against the
// coursework handout's own renders (see tests/test_official_scenes.cpp): the
// handout maps the 0.25 background to 87/255, a gentle lift, not sRGB.
inline constexpr float kCourseworkDisplayGamma = 1.22f;
// Path mode renders physical radiance: shown with the usual display gamma.
inline constexpr float kPathDisplayGamma = 2.2f;

struct SessionOptions {
  std::string scene_path;
  // A scene already loaded (the Python module's caustica.load/load_dict):
  // rendered instead of reading scene_path, which then only names it.
  std::shared_ptr<const Scene> scene;
  std::optional<RenderMode> mode;  // --mode; default: the scene's rendermode
  int width = 0;                   // 0: from the camera (or derived keeping the aspect)
  int height = 0;
  std::string device;  // --device spec
  bool use_kernel_cache = true;
  bool strict = false;  // unknown scene keys are errors instead of warnings
  std::optional<int> gltf_camera;  // --camera: a glTF scene's /cameras/N (default: the first placed)
  size_t local_size = 64;  // work-group size of the stage launches
  bool profile_stages = false;  // device time per stage kernel in RenderStats::stage_ms (bench)
  int spp = 0;                  // path: samples per pixel (passes); 0: the default (kDefaultPathSpp)
  int first_pass = 0;           // path: --passes START:END renders passes [first_pass, spp) only
  double time_limit_s = 0.0;    // path: stop at this wall time (with --spp: whichever first); 0: none
  uint32_t seed = 0;            // path: sample sequence seed
  bool independent_samples = false;  // path: independent uniforms instead of Sobol-Burley (comparisons)
  bool error_estimate = true;   // path: the film keeps the half buffer, passes [P, N) (self-estimated error)
  bool adaptive = true;         // path: adaptive sampling (--no-adaptive: uniform)
  CausticsMode caustics = CausticsMode::Auto;  // path: the photon pass
  bool check_numerics = false;  // path: count BSDF weights per bounce (--check-numerics)
  bool aux_passes = false;      // path: the film's albedo, normal and depth passes (--denoise, .exr, --aov-dir)
  LightSampler light_sampler = LightSampler::Auto;  // path: --light-sampler (auto: the tree above a handful of lights)
  KernelShape kernel_shape = KernelShape::Auto;  // path: --kernel-shape (auto: paths on a CPU device)
  uint32_t photons = 0;         // path: photons per pass; 0: RenderSettings' default
  float caustic_radius = 0.0f;  // path: initial gather radius; 0: from the scene's size
  bool open_ended = false;      // path: no default sample count (a target error decides), unless --spp
  // --bvh: spatial splits (SBVH) by default; "fast" for huge scenes.
  BvhBuildOptions::Quality bvh_quality = BvhBuildOptions::Quality::Spatial;
  // Applied to the loaded scene before anything is derived from it (tests:
  // the stiff-case suite scales and moves whole scenes, tests/stiff/).
  std::function<void(Scene&)> edit_scene;
  // Applied to the features decided from the scene and the options, before
  // the program is built and anything binds it: the render settings follow
  // the features, so the host binds what the program declares (tests: the
  // feature-flag combinations, tests/test_feature_combinations.cpp).
  std::function<void(SceneFeatures&)> edit_features;
};

inline constexpr int kDefaultPathSpp = 64;

struct Session {
  Scene scene;
  RenderMode mode = RenderMode::Phong;  // --mode, else the scene's rendermode: decided here, once
  SceneFeatures features;
  Bvh bvh;       // binary: the host trace of `caustica bench` (host/bench/host_trace.cpp) walks it
  WideBvh wide;  // collapsed from bvh: what the kernels traverse
  std::shared_ptr<Runtime> runtime;  // Runtime::shared: one per device in a process
  BuiltProgram program;
  RenderSettings settings;
  std::unique_ptr<DeviceScene> device_scene;
  std::unique_ptr<Renderer> renderer;
  double load_ms = 0.0;
  double upload_ms = 0.0;
};

std::unique_ptr<Session> prepare_session(const SessionOptions& options);

// --mode: "" (the scene decides), "binary", "phong" or "path"; anything else throws.
std::optional<RenderMode> parse_render_mode(const std::string& name);

// --bvh: "fast", "sah" or "spatial"; anything else throws.
BvhBuildOptions::Quality parse_bvh_quality(const std::string& name);
const char* bvh_quality_name(BvhBuildOptions::Quality quality);

// Width/height after CLI overrides: one given keeps the camera's aspect.
// Throws, naming the limit, beyond limits::kMaxImageSide / kMaxImagePixels.
void resolve_image_size(const CameraDesc& camera, int width_override, int height_override, int* width, int* height);
// The same limits on a size as given (0: not given); `what` names it in the error.
void check_image_size_limits(const std::string& what, long long width, long long height);

}  // namespace caustica
