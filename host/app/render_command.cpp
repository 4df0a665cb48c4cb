#include "host/app/render_command.h"

#include "host/app/spp_heatmap.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <thread>

#include "host/app/distributed_render.h"
#include "host/app/error_monitor.h"
#include "host/app/cli_numbers.h"
#include "host/app/film_outputs.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/lights/light_types.h"
#include "host/limits.h"
#include "host/image/tonemap.h"
#include "host/render/render_state.h"

namespace caustica {
namespace {

std::string format_error(double e) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", e);
  return b;
}

std::string format_seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f s", s);
  return b;
}

// Progress on stderr: a rewritten line on a terminal, one line a second
// otherwise; silent for renders that finish within a second.
class ProgressReporter {
 public:
  explicit ProgressReporter(bool enabled) : enabled_(enabled), tty_(isatty(2)) {}
  void update(const PassProgress& p) {
    if (!enabled_) return;
    const double s = seconds();
    const double samples = double(p.pixels_total) * p.pass + double(p.pixels_done);  // pixel samples done
    // This run's: a resumed render's rate and time left leave out the state's.
    const double run_samples = samples - double(p.pixels_total) * p.first_pass;
    const bool open_ended = p.passes == std::numeric_limits<int>::max();
    const double total = double(p.pixels_total) * p.passes;
    const uint64_t rays = p.stats ? p.stats->rays() : 0;
    if (s < 1.0 || (!tty_ && s - last_ < 1.0 && samples < total)) return;
    last_ = s;
    // Time left: to the sample target at the current rate, or to the time
    // limit, or to the target error as projected, whichever comes first.
    double left = run_samples > 0 && !open_ended ? s * (total - samples) / run_samples : 1e300;
    if (p.time_limit_s > 0.0) left = std::min(left, std::max(0.0, p.time_limit_s - p.seconds));
    std::optional<double> to_target = monitor_ ? monitor_->seconds_to_target(p.seconds) : std::nullopt;
    if (to_target) left = std::min(left, *to_target);
    char target[32];
    if (open_ended) std::snprintf(target, sizeof target, "%s", "-");
    else std::snprintf(target, sizeof target, "%d", p.passes);
    std::string error;
    if (monitor_ && monitor_->estimate()) {
      error = ", relMSE ~" + format_error(*monitor_->estimate());
      if (to_target) error += " (target in " + format_seconds(*to_target) + ")";
    }
    std::fprintf(stderr, "%s[caustica] %.2f/%s spp, %.3g samples/s, %.2f Mrays/s%s, %.1f s elapsed, %s left%s",
                 tty_ ? "\r" : "", samples / double(p.pixels_total), target, run_samples / s, rays / s * 1e-6,
                 error.c_str(), s, left < 1e299 ? format_seconds(left).c_str() : "?", tty_ ? "\x1b[K" : "\n");
    printed_ = true;
  }
  void finish() {
    if (printed_ && tty_) std::fprintf(stderr, "\n");
  }
  void set_error_monitor(const ErrorMonitor* monitor) { monitor_ = monitor; }

 private:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool enabled_, tty_, printed_ = false;
  double last_ = 0.0;
  const ErrorMonitor* monitor_ = nullptr;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// --check-numerics: what the film dropped, and per scattering event the
// BSDF samples' mean weight (largest channel; a mean above 1 means the
// scene's materials or the sampling gain energy) and how many exceeded 1.
void print_numerics_report(const RenderStats& stats, RenderMode mode) {
  std::fprintf(stderr, "[caustica] numerics: %llu NaN/Inf and %llu negative contributions dropped, %llu clamped\n",
               (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
               (unsigned long long)stats.film.clamped);
  if (mode != RenderMode::Path || stats.numerics.size() != NUMERICS_COUNTERS) {
    std::fprintf(stderr, "[caustica] numerics: per-bounce BSDF weights are counted in path mode only\n");
    return;
  }
  std::fprintf(stderr, "[caustica] numerics: %llu non-finite BSDF weights\n",
               (unsigned long long)stats.numerics[NUMERICS_NONFINITE]);
  bool gain = false;
  for (uint32_t d = 0; d < NUMERICS_DEPTHS; ++d) {
    const uint64_t n = stats.numerics[3 * d], above = stats.numerics[3 * d + 2];
    if (n == 0) continue;
    const double mean = double(stats.numerics[3 * d + 1]) / NUMERICS_WEIGHT_SCALE / double(n);
    gain = gain || mean > 1.001;
    std::fprintf(stderr, "[caustica] numerics: bounce %u%s: %llu BSDF samples, mean weight %.4f, %.3f%% above 1%s\n",
                 d + 1, d + 1 == NUMERICS_DEPTHS ? "+" : "", (unsigned long long)n, mean, 100.0 * double(above) / n,
                 mean > 1.001 ? "  <- energy gain" : "");
  }
  if (gain)
    std::fprintf(stderr, "[caustica] numerics: a mean weight above 1 gains energy at that bounce: check material "
                         "colours above 1 or the BSDF's sampling\n");
}

// The report's header: what was rendered, where, and what it cost before
// the first sample (the rows' seconds start at the first sample).
std::vector<std::pair<std::string, std::string>> report_header(const Session& session, const RenderArgs& a,
                                                               int resumed_passes) {
  char buf[128];
  std::vector<std::pair<std::string, std::string>> h;
  h.emplace_back("scene", session.scene.source_path);
  std::snprintf(buf, sizeof buf, "%s %dx%d %s seed %u%s", render_mode_name(session.mode), session.settings.width,
                session.settings.height,
                session.settings.sampler == SAMPLER_INDEPENDENT ? "independent" : "sobol", session.settings.seed,
                session.mode != RenderMode::Path ? "" : session.settings.adaptive ? " adaptive" : " uniform");
  h.emplace_back("mode", buf);
  h.emplace_back("device", session.runtime->device_info().name + " (" +
                               session.runtime->device_info().platform_name + ")");
  std::snprintf(buf, sizeof buf, "%.3f (%s)", session.program.build_ms / 1e3,
                session.program.from_cache ? "cached" : "cold");
  h.emplace_back("kernel_build_s", buf);
  std::snprintf(buf, sizeof buf, "%.3f", session.bvh.build_ms / 1e3);
  h.emplace_back("bvh_build_s", buf);
  if (!a.reference.empty()) h.emplace_back("reference", a.reference);
  if (!a.resume.empty()) h.emplace_back("resumed_from", a.resume + " at " + std::to_string(resumed_passes) + " spp");
  return h;
}

// A number option read strictly: all of the text must be one finite number
// in [lo, hi] (CLI11 would take '' as "not given" and "nan" as a number).
float parse_number_option(const std::string& option, const std::string& text, double lo, double hi,
                          const std::string& what) {
  char* end = nullptr;
  const double d = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(d) || d < lo || d > hi)
    throw Error(option + " '" + text + "': expected " + what);
  return static_cast<float>(d);
}

// Where an output will go must exist before the render starts.
void check_output_dir(const std::string& option, const std::string& path) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
    throw Error(option + " " + path + ": the directory '" + dir.string() + "' does not exist");
}

const char* bvh_quality_name(BvhBuildOptions::Quality q) {
  switch (q) {
    case BvhBuildOptions::Quality::Fast: return "fast";
    case BvhBuildOptions::Quality::Sah: return "sah";
    case BvhBuildOptions::Quality::Spatial: return "spatial";
  }
  return "unknown";
}

}  // namespace

CLI::App* add_render_command(CLI::App& app, RenderArgs& a) {
  CLI::App* render_cmd = app.add_subcommand("render", "render a scene to an image (.ppm .png .pfm .exr)");
  render_cmd->add_option("scene", a.session.scene_path, "scene JSON file, or a glTF 2.0 file (.gltf, .glb)")->required();
  render_cmd->add_option("--camera", a.session.gltf_camera,
                         "glTF scenes: render from the file's camera N (/cameras/N; default: the first placed)")
      ->check(CLI::NonNegativeNumber);
  render_cmd->add_option("-o,--output", a.output, "output image; the extension picks the format")
      ->check(non_empty_path());
  render_cmd->add_option("--mode", a.mode, "binary | phong | path (default: the scene's rendermode)");
  render_cmd->add_option("--width", a.session.width, "image width (keeps the camera's aspect unless --height)");
  render_cmd->add_option("--height", a.session.height, "image height");
  render_cmd->add_option("--tonemap", a.tonemap, "linear | reinhard | aces (default linear; aces in path mode)");
  render_cmd->add_option_function<std::string>(
      "--exposure",
      [&a](const std::string& s) {
        const double stops = limits::kMaxExposureStops;
        a.exposure = parse_number_option("--exposure", s, -stops, stops,
                                         "an exposure in stops, a number within [-" + std::to_string(int(stops)) +
                                             ", " + std::to_string(int(stops)) + "] (the limit)");
      },
      "exposure in stops (default: the camera's \"exposure\")");
  render_cmd->add_option_function<std::string>(
      "--gamma",
      [&a](const std::string& s) {
        a.gamma = parse_number_option("--gamma", s, 1e-3, 1e3, "a display gamma, a number within [0.001, 1000]");
      },
      "display gamma of 8-bit outputs (default 1.22 as the coursework handout; 2.2 in path mode)");
  render_cmd->add_option("--device", a.session.device,
                         "OpenCL device: index, name substring, cpu or gpu (env CAUSTICA_DEVICE)");
  render_cmd->add_flag("--no-cache", [&a](int64_t) { a.session.use_kernel_cache = false; },
                       "rebuild kernels instead of loading cached binaries");
  render_cmd->add_option_function<std::string>(
      "--bvh", [&a](const std::string& q) { a.session.bvh_quality = parse_bvh_quality(q); },
      "BVH build: spatial (SBVH, default), sah, or fast for huge scenes");
  render_cmd->add_flag("--strict", a.session.strict, "unknown scene keys are errors, not warnings");
  render_cmd->add_option("--spp", a.session.spp, "path: samples per pixel (default 64)")->check(CLI::PositiveNumber);
  render_cmd->add_option("--seed", a.session.seed, "path: seed of the sample sequences (default 0)");
  render_cmd->add_option("--time", a.session.time_limit_s,
                         "path: stop after the pass that reaches SECONDS (with --spp: whichever comes first)")
      ->check(finite_positive(limits::kMaxSeconds));
  render_cmd->add_option("--write-every", a.write_every_s,
                         "path: also write the image (and --spp-map) every SECONDS")
      ->check(finite_positive(limits::kMaxSeconds));
  render_cmd->add_option("--spp-map", a.spp_map,
                         "path: draw each pixel's sample count as a heatmap with a colour bar (.png/.svg, through "
                         "gnuplot); an .exr output always carries it as its 'spp' channel")
      ->check(non_empty_path());
  render_cmd->add_option_function<std::string>(
      "--sampler",
      [&a](const std::string& s) {
        if (s != "sobol" && s != "independent") throw CLI::ValidationError("--sampler", "expected sobol or independent");
        a.session.independent_samples = s == "independent";
      },
      "path: sobol (Owen-scrambled Sobol-Burley, default) or independent");
  render_cmd->add_flag("-v,--verbose", a.verbose, "print features, build, BVH and render times");
  render_cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  render_cmd->add_option("--report", a.report,
                         "write error against run time (CSV: seconds, spp, estimated and true error) to FILE")
      ->check(non_empty_path());
  render_cmd->add_option("--reference", a.reference,
                         "linear reference image (.pfm/.exr, same size): measure true MSE, relMSE, MAE while rendering")
      ->check(non_empty_path());
  render_cmd->add_option("--plot", a.plot, "draw the --report as error against time (.png/.svg, through gnuplot)")
      ->check(non_empty_path());
  render_cmd->add_option("--target-error", a.target_error,
                         "path: stop when the estimated relMSE reaches E (with --time/--spp: whichever first)")
      ->check(finite_positive());
  render_cmd->add_option_function<std::string>(
      "--caustics", [&a](const std::string& m) { a.session.caustics = parse_caustics_mode(m); },
      "path: photon-mapped caustics: auto (default: with smooth metal or glass, where its work pays), on, off");
  render_cmd->add_option("--photons", a.session.photons, "path: photons emitted per photon map (default: one per pixel, 16384 to 1048576)")
      ->check(CLI::Range(1u, 1u << 22));
  render_cmd->add_option("--caustic-radius", a.session.caustic_radius,
                         "path: every pixel's initial photon gather radius (default: its camera path's footprint)")
      ->check(finite_positive());
  render_cmd->add_option_function<std::string>(
      "--kernel-shape", [&a](const std::string& s) { a.session.kernel_shape = parse_kernel_shape(s); },
      "path: how the stages run: auto (default: paths on a CPU device, the wavefront on a GPU), wavefront (kernels "
      "over queues) or paths (whole paths per work-item, one kernel); the same image either way");
  render_cmd->add_flag("--check-numerics", a.session.check_numerics,
                       "path: count NaN/Inf and negative samples and the BSDF weights of every bounce (energy gain), "
                       "and report them");
  render_cmd->add_flag("--no-error-estimate", a.no_error_estimate,
                       "path: leave out the film's half buffer (no self-estimated error, so no adaptive sampling)");
  render_cmd->add_option("--checkpoint", a.checkpoint,
                         "write the render's state to FILE (atomically) every --checkpoint-every seconds, between "
                         "waves, and at the end; --resume continues from it")
      ->check(non_empty_path());
  render_cmd->add_option_function<double>(
      "--checkpoint-every", [&a](const double& s) { a.checkpoint_every_s = s; },
      "seconds between --checkpoint writes (default 60)")
      ->check(finite_positive(limits::kMaxSeconds));
  render_cmd->add_option("--resume", a.resume,
                         "continue the render saved in FILE by --checkpoint, up to --spp (or for --time); the scene "
                         "and every setting that changes the image must match it")
      ->check(non_empty_path());
  render_cmd->add_option("--passes", a.passes,
                         "path: render passes START:END only (absolute pass indices: the same samples as those "
                         "passes of a full render), for `caustica merge`; needs --no-adaptive and no photon pass");
  render_cmd->add_flag("--denoise", a.denoise,
                       "path: every output's main image is denoised by Intel Open Image Denoise, guided by the "
                       "film's albedo and normal passes (an .exr keeps the raw film as its 'beauty' layer)");
  render_cmd->add_option("--denoise-quality", a.denoise_quality, "path: fast | balanced | high (default): OIDN's filter quality")
      ->check(CLI::IsMember({"fast", "balanced", "high"}));
  render_cmd->add_option("--denoise-guides", a.denoise_guides,
                         "path: auto (default: noisy with a lens or smooth glass, else clean) | clean | noisy | "
                         "prefilter (clean them first: OIDN's best, 3x the time)")
      ->check(CLI::IsMember({"auto", "clean", "noisy", "prefilter"}));
  render_cmd->add_option("--aov-dir", a.aov_dir,
                         "path: also write each pass as its own .exr in DIR (beauty, denoised, albedo, normal, "
                         "depth, variance, spp)")
      ->check(non_empty_path());
  render_cmd->add_flag("--adaptive,!--no-adaptive", a.session.adaptive,
                       "path: adaptive sampling, the default: after 16 spp, each wave's samples go where the "
                       "estimated error is (--no-adaptive: every pixel alike)");
  return render_cmd;
}

void check_render_options(RenderArgs& a) {
  // Every option is checked before the scene is read: a typo in one must not
  // cost a render (the size against the scene's camera is checked as soon as
  // the scene is read, in prepare_session).
  a.session.mode = parse_render_mode(a.mode);
  if (a.output.empty()) a.output = std::filesystem::path(a.session.scene_path).stem().string() + ".png";
  check_output_image_path(a.output);
  if (!a.tonemap.empty()) {
    try {
      parse_tonemap(a.tonemap);
    } catch (const Error& e) {
      throw Error("--tonemap: " + std::string(e.what()));
    }
  }
  if (a.session.width < 0 || a.session.height < 0) throw Error("--width/--height must be positive");
  check_image_size_limits("--width/--height", a.session.width, a.session.height);
  if (!a.report.empty()) check_output_dir("--report", a.report);
  if (!a.plot.empty()) {
    const std::string ext = std::filesystem::path(a.plot).extension().string();
    if (ext != ".png" && ext != ".svg") throw Error("--plot " + a.plot + ": expected a .png or .svg file name");
    check_output_dir("--plot", a.plot);
  }
  if (!a.spp_map.empty()) {
    const std::string ext = std::filesystem::path(a.spp_map).extension().string();
    if (ext != ".png" && ext != ".svg") throw Error("--spp-map " + a.spp_map + ": expected a .png or .svg file name");
    check_output_dir("--spp-map", a.spp_map);
  }
  if (!a.plot.empty() && a.report.empty()) throw Error("--plot " + a.plot + ": needs --report (the plot is drawn from it)");
  if (a.target_error > 0.0 && a.no_error_estimate)
    throw Error("--target-error needs the error estimate that --no-error-estimate leaves out");
  if (a.checkpoint_every_s && a.checkpoint.empty())
    throw Error("--checkpoint-every needs --checkpoint (the file the state is written to)");
  if (!a.checkpoint.empty()) {
    check_output_dir("--checkpoint", a.checkpoint);
    // The state is written atomically beside it and renamed over it: a
    // device or a folder there (a link to /dev/full, say) is no state file.
    std::error_code ec;
    const auto status = std::filesystem::status(a.checkpoint, ec);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
      throw Error("--checkpoint " + a.checkpoint + ": exists and is not a regular file (a state file is written "
                  "beside it and renamed over it)");
    // Nothing the render writes or reads may be the state it saves.
    auto same = [&](const std::string& other) {
      if (other.empty()) return false;
      std::error_code e1, e2;
      const auto x = std::filesystem::weakly_canonical(a.checkpoint, e1);
      const auto y = std::filesystem::weakly_canonical(other, e2);
      return !e1 && !e2 && x == y;
    };
    for (const auto& [option, path] : {std::pair<const char*, const std::string*>{"-o", &a.output},
                                       {"--spp-map", &a.spp_map}, {"--report", &a.report}, {"--plot", &a.plot},
                                       {"--reference", &a.reference}})
      if (same(*path))
        throw Error("--checkpoint " + a.checkpoint + " and " + option + " " + *path +
                    " name the same file: one would overwrite the other");
  }
  if (a.denoise && !Denoiser::available()) throw Error("--denoise: " + Denoiser::missing_message());
  if (!a.aov_dir.empty()) check_output_dir("--aov-dir", a.aov_dir);  // DIR's parent exists (DIR is made)
  // The film's aux passes: what the denoiser and an .exr's layers take.
  a.session.aux_passes = a.denoise || !a.aov_dir.empty() || lower_extension(a.output) == ".exr";
  const bool distributed = a.ranks && a.ranks->size() > 1;
  if (distributed) check_distributed_options(a);
  if (!a.passes.empty()) {
    const auto [first, end] = parse_pass_range(a.passes);
    if (a.session.spp > 0) throw Error("--passes " + a.passes + " and --spp: give one (--passes ends at END)");
    if (a.session.time_limit_s > 0.0 || a.target_error > 0.0)
      throw Error("--passes " + a.passes + ": a render of a fixed set of passes takes no --time or --target-error");
    if (a.session.adaptive)
      throw Error("--passes " + a.passes + ": adaptive sampling plans each wave from the error of the whole film, "
                  "which a render of some of its passes does not hold: add --no-adaptive");
    a.session.first_pass = first;
    a.session.spp = end;
  }
}

int run_render(RenderArgs& a) {
  check_render_options(a);
  const bool distributed = a.ranks && a.ranks->size() > 1;
  // A state that cannot be read, or is damaged, fails before the scene is read.
  std::optional<RenderState> resume;
  if (!a.resume.empty()) resume = read_render_state(a.resume);
  // A state made with the aux passes resumes with them (whatever this
  // render's outputs); one made without cannot give them.
  if (resume) {
    for (const auto& [name, value] : resume->identity)
      if (name == "aux passes") {
        if (value == "on") a.session.aux_passes = true;
        else if (a.session.aux_passes)
          throw Error(a.resume + ": a state rendered without the aux passes (albedo, normal, depth), which " +
                      std::string(a.denoise ? "--denoise" : !a.aov_dir.empty() ? "--aov-dir" : "an .exr output") +
                      " needs: write a .pfm or .png, or render again");
      }
  }
  // A bad reference fails before anything is built or rendered.
  std::optional<ImageF> reference;
  const bool reference_given = !a.reference.empty();
  if (!a.reference.empty()) {
    if (!is_hdr_path(a.reference))
      throw Error("--reference " + a.reference + ": expected a linear .pfm or .exr image");
    try {
      reference = read_hdr_image(a.reference);
    } catch (const Error& e) {
      throw Error("--reference: " + std::string(e.what()));
    }
  }
  a.session.error_estimate = !a.no_error_estimate;
  if (a.no_error_estimate) a.session.adaptive = false;  // it allocates by that estimate
  a.session.open_ended = a.target_error > 0.0;
  const auto session = prepare_session(a.session);
  if (reference && (reference->width != session->settings.width || reference->height != session->settings.height))
    throw Error("--reference " + a.reference + ": the reference is " + std::to_string(reference->width) + "x" +
                std::to_string(reference->height) + " but the render is " + std::to_string(session->settings.width) +
                "x" + std::to_string(session->settings.height) + " (set --width/--height to match)");
  if (a.target_error > 0.0 && session->mode != RenderMode::Path)
    throw Error("--target-error: only path mode is stochastic; binary and phong images are exact after one pass");
  if (!a.spp_map.empty() && session->mode != RenderMode::Path)
    throw Error("--spp-map: only path mode takes several samples a pixel");
  if ((a.denoise || !a.aov_dir.empty()) && session->mode != RenderMode::Path)
    throw Error(std::string(a.denoise ? "--denoise" : "--aov-dir") +
                ": path mode only (binary and phong images are exact, with no noise and no passes)");
  if (!a.aov_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.aov_dir, ec);
    if (ec) throw Error("--aov-dir " + a.aov_dir + ": cannot create it: " + ec.message());
  }
  std::unique_ptr<Denoiser> denoiser;
  if (a.denoise) {
    DenoiserOptions options;
    options.quality = parse_denoise_quality(a.denoise_quality);
    const DeviceInfo& device = session->runtime->device_info();
    options.gpu = device.type == "gpu";
    // OIDN's threads are the render's: an OpenCL CPU device's compute units
    // (PoCL's threads, which POCL_MAX_PTHREAD_COUNT limits).
    options.threads = device.type == "cpu" && device.compute_units > 0
                          ? int(device.compute_units)
                          : std::max(1, int(std::thread::hardware_concurrency()));
    denoiser = std::make_unique<Denoiser>(options);
    if (a.verbose) std::fprintf(stderr, "[caustica] denoiser: %s\n", denoiser->description().c_str());
  }
  // Path mode only: binary and phong have no adaptive sampling.
  if (distributed && session->settings.adaptive)
    throw Error(ranks_text(a) + ": adaptive sampling plans each wave from the error of the whole film, which no "
                "rank holds: add --no-adaptive (docs/distributed.md)");
  if (!a.passes.empty()) {
    if (session->mode != RenderMode::Path)
      throw Error("--passes " + a.passes + ": only path mode takes several passes (binary and phong take one)");
    if (session->settings.caustics)
      throw Error("--passes " + a.passes + ": the photon pass (--caustics " +
                  std::string(a.session.caustics == CausticsMode::On ? "on" : "auto, which found caustics here") +
                  ") keeps per-pixel statistics that are not sums of passes: add --caustics off");
  }
  // The state's identity: what a resumed state must match, and what a
  // checkpoint records.
  StateIdentity identity;
  if (!a.checkpoint.empty() || resume) {
    identity = render_identity(scene_hash(session->scene), session->mode, session->settings,
                               bvh_quality_name(a.session.bvh_quality));
  }
  if (resume) {
    check_render_state(a.resume, *resume, identity);
    try {
      session->renderer->check_state(*resume);
    } catch (const Error& e) {
      throw Error(a.resume + ": " + e.what());
    }
    // The pass range (a state of passes [2, 4) resumed to --spp 4 wrote a
    // 2-spp image) and the sampler's state: Renderer::check_state.
  }
  const int resumed_passes = resume ? resume->film.passes : 0;
  const Scene& scene = session->scene;
  // Path tracing never reaches a point or spot light through glass or in a mirror:
  // without the photon pass those caustics are missing, and the error
  // estimate, which sees only noise, cannot tell.
  if (!a.quiet && session->mode == RenderMode::Path && a.session.caustics == CausticsMode::Off &&
      has_delta_light(scene) && analyse_scene(scene, RenderMode::Path, CausticsMode::Auto).caustics)
    std::fprintf(stderr,
                 "[caustica] warning: --caustics off: the caustics of this scene's point and spot lights (through glass, in "
                 "mirrors) are missing from the image, and from its error estimate\n");
  if (a.verbose) {
    std::fprintf(stderr, "[caustica] scene %s: %zu spheres, %zu cylinders, %zu triangles, %zu lights, %zu materials (load %.1f ms)\n",
                 scene.source_path.c_str(), scene.spheres.size(), scene.cylinders.size(), scene.triangles.size(),
                 scene.light_count(), scene.materials.size(), session->load_ms);
    for (const auto& m : scene.meshes)
      std::fprintf(stderr, "[caustica] mesh %s: %zu triangles (%zu degenerate dropped), loaded in %.1f ms\n",
                   m.file.c_str(), m.triangles, m.dropped_degenerate, m.load_ms);
    std::fprintf(stderr, "[caustica] features: %s\n[caustica] kernel options:%s\n", session->features.describe().c_str(),
                 session->features.build_options().c_str());
    std::fprintf(stderr, "[caustica] device: %s (%s)\n", session->runtime->device_info().name.c_str(),
                 session->runtime->device_info().platform_name.c_str());
    if (session->mode == RenderMode::Path)
      std::fprintf(stderr, "[caustica] kernel shape: %s (--kernel-shape %s)\n",
                   kernel_shape_name(session->settings.kernel_shape), kernel_shape_name(a.session.kernel_shape));
    std::fprintf(stderr, "[caustica] kernel build: %.1f ms (%s)\n", session->program.build_ms,
                 session->program.from_cache ? "cached" : "cold");
    std::fprintf(stderr, "[caustica] BVH build: %.2f ms, %zu nodes, SAH cost %.2f, depth %d\n", session->bvh.build_ms,
                 session->bvh.nodes.size(), session->bvh.sah_cost, session->bvh.max_depth);
  }
  RenderStats stats;
  ProgressReporter progress(!a.quiet);
  DisplaySettings display;
  display.tonemap = parse_tonemap(!a.tonemap.empty() ? a.tonemap
                                                     : session->mode == RenderMode::Path ? "aces" : "linear");
  display.exposure_scale = std::exp2(a.exposure ? *a.exposure : scene.camera.exposure);
  display.gamma = a.gamma ? *a.gamma : session->mode == RenderMode::Path ? kPathDisplayGamma : kCourseworkDisplayGamma;
  ErrorMonitorOptions error_options;
  error_options.report_path = a.report;
  error_options.plot_path = a.plot;
  error_options.reference = std::move(reference);
  error_options.target_error = a.target_error;
  // Ranks sum their films for every measurement: with only a target error
  // to watch, measure from 16 passes on where it is projected (1.43 s of a
  // 24 s Cornell box render on 2 ranks went to 8 geometric ones).
  if (a.ranks && a.ranks->size() > 1 && a.target_error > 0.0 && a.report.empty() && a.plot.empty() &&
      !error_options.reference)
    error_options.sparse_from = 16;
  error_options.exposure_scale = display.exposure_scale;
  error_options.header = report_header(*session, a, resumed_passes);
  error_options.denoiser = denoiser.get();
  // Guides noisy in kind: a lens, or smooth glass splitting paths.
  const GuideMode guides = a.denoise_guides == "auto"
                              ? guide_mode_for(scene.camera.aperture_radius > 0.0f, session->features.refraction)
                              : parse_guide_mode(a.denoise_guides);
  error_options.guides = guides;
  ErrorMonitor monitor(std::move(error_options));
  progress.set_error_monitor(&monitor);
  double last_write = 0.0, render_seconds = 0.0, last_checkpoint = 0.0;
  const double checkpoint_every = a.checkpoint_every_s.value_or(kDefaultCheckpointSeconds);
  int checkpoint_passes = -1;  // the latest checkpoint's
  Renderer* shown = session->renderer.get();  // the renderer whose film is written
  auto write_checkpoint_of = [&](const Renderer& renderer) {
    if (renderer.film().passes() == checkpoint_passes) return;  // the same state again
    RenderState state = renderer.state();
    state.identity = identity;
    write_render_state(a.checkpoint, state);
    checkpoint_passes = state.film.passes;
    if (a.verbose)
      std::fprintf(stderr, "[caustica] checkpoint %s at %d spp\n", a.checkpoint.c_str(), state.film.passes);
  };
  auto write_checkpoint = [&] { write_checkpoint_of(*shown); };
  const bool path = session->mode == RenderMode::Path;
  // The image, with its per-pixel sample counts where they can go: an .exr
  // output's "spp" channel, and the --spp-map heatmap.
  FilmOutputOptions output_options;
  output_options.output = a.output;
  output_options.aov_dir = a.aov_dir;
  output_options.display = display;
  output_options.denoiser = denoiser.get();
  output_options.verbose = a.verbose;
  output_options.guides = guides;
  // Path mode: the film's outputs (denoised, with its passes); otherwise
  // the image.
  auto write_outputs = [&](const ImageF& image, const Film& film) {
    if (path)
      write_film_outputs(output_options, film);
    else
      write_image(a.output, image, display);
    if (!a.spp_map.empty()) {
      char title[160];
      std::snprintf(title, sizeof title, "%s: samples per pixel (mean %d, %s)",
                    std::filesystem::path(session->scene.source_path).filename().string().c_str(), film.passes(),
                    session->settings.adaptive ? "adaptive" : "uniform");
      write_spp_heatmap(a.spp_map, film.width(), film.height(), film.pixel_spp(), title);
    }
  };
  DistributedResult summed;
  if (distributed) {
    // The monitor is rank 0's, and rounds wait for its decisions only when
    // it has something to decide.
    const bool monitored = !a.report.empty() || reference_given || a.target_error > 0.0;
    summed = render_distributed(*session, *a.ranks, &stats,
                                a.ranks->rank() == 0 ? ProgressCallback([&](const PassProgress& p) { progress.update(p); })
                                                     : ProgressCallback{},
                                a.ranks->rank() == 0 && monitored ? &monitor : nullptr, resume ? &*resume : nullptr,
                                DistributedCheckpoint{checkpoint_every, a.checkpoint.empty()
                                                                            ? std::function<void(const Renderer&)>()
                                                                            : write_checkpoint_of});
    if (a.ranks->rank() != 0) return 0;
    shown = summed.summed.get();
    render_seconds = summed.seconds;
    stats.render_ms = summed.seconds * 1e3;
    if (a.verbose)
      std::fprintf(stderr,
                   "[caustica] %d ranks: %s summed on rank 0 in %d reductions, %.3f s (film reads %.3f s, waiting for "
                   "ranks %.3f s, MPI %.3f s, restore %.3f s); its error measurements %.3f s\n",
                   a.ranks->size(), shown->film().held().describe().c_str(), summed.reductions,
                   summed.reduction_seconds, summed.read_seconds, summed.wait_seconds, summed.mpi_seconds,
                   summed.restore_seconds, summed.measure_seconds);
    if (a.verbose && summed.by_pixels)
      std::fprintf(stderr,
                   "[caustica] %d ranks shared the photon pass by pixels: %u photon maps gathered to every rank, "
                   "%.0f bytes a map; rank 0 waited %.4f s a map for the slowest rank and gathered in %.4f s a map\n",
                   a.ranks->size(), stats.photon_maps,
                   double(summed.photon_traffic.bytes) / std::max(1u, stats.photon_maps),
                   summed.photon_traffic.wait_seconds / std::max(1u, stats.photon_maps),
                   summed.photon_traffic.gather_seconds / std::max(1u, stats.photon_maps));
  }
  const ImageF image = distributed ? summed.image : session->renderer->render(
      &stats, [&](const PassProgress& p) { progress.update(p); },
      [&](const Film& film, double seconds) {
        render_seconds = seconds;
        const bool go_on = monitor.on_pass(film, seconds);
        if (a.write_every_s > 0.0 && seconds - last_write >= a.write_every_s) {
          last_write = seconds;
          write_outputs(film.mean(), film);
        }
        // Between waves: the film holds whole waves only.
        if (!a.checkpoint.empty() && seconds - last_checkpoint >= checkpoint_every) {
          last_checkpoint = seconds;
          write_checkpoint();
        }
        return go_on;
      },
      resume ? &*resume : nullptr);
  progress.finish();
  write_outputs(image, shown->film());
  if (!a.checkpoint.empty()) write_checkpoint();
  monitor.finish(shown->film(), render_seconds);
  if (a.verbose) {
    std::fprintf(stderr,
                 "[caustica] render: %.1f ms, %dx%d, %llu camera + %llu secondary + %llu shadow + %llu photon rays "
                 "(%.2f Mrays/s)%s\n",
                 stats.render_ms, image.width, image.height, (unsigned long long)stats.camera_rays,
                 (unsigned long long)stats.secondary_rays, (unsigned long long)stats.shadow_rays,
                 (unsigned long long)stats.photon_rays, stats.rays() / (stats.render_ms * 1e3),
                 stats.chunk_retries ? " (queue overflow: chunks split)" : "");
    std::fprintf(stderr,
                 "[caustica] host traffic: %llu kernel launches, %llu blocking transfers, %llu count reads "
                 "(non-blocking)\n",
                 (unsigned long long)stats.launches, (unsigned long long)stats.blocking_transfers,
                 (unsigned long long)stats.count_reads);
    std::fprintf(stderr,
                 "[caustica] film: %d passes; dropped %llu NaN/Inf and %llu negative contributions, clamped %llu, "
                 "%llu below its resolution\n",
                 stats.passes, (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
                 (unsigned long long)stats.film.clamped, (unsigned long long)stats.film.underflow);
    if (stats.photon_rays > 0) {
      const PhotonGatherStats& g = stats.photon_gathers;
      auto per = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
      std::fprintf(stderr,
                   "[caustica] photons: %u maps in %.3f s (%.1f%% of the render), %llu rays, %llu stored; gathers at "
                   "visible points %llu (%.1f photons visited each), at later receivers %llu (%.1f each)\n",
                   stats.photon_maps, stats.photon_seconds, 100.0 * stats.photon_seconds / (stats.render_ms * 1e-3),
                   (unsigned long long)stats.photon_rays, (unsigned long long)stats.photons_stored,
                   (unsigned long long)g.gathers_d1, per(g.visits_d1, g.gathers_d1),
                   (unsigned long long)g.gathers_later, per(g.visits_later, g.gathers_later));
    }
    if (!stats.caustics_decision.empty()) {
      std::string d = stats.caustics_decision;
      for (size_t at = 0; (at = d.find('\n', at)) != std::string::npos; at += 12) d.replace(at, 1, "\n[caustica] ");
      std::fprintf(stderr, "[caustica] %s\n", d.c_str());
    }
  }
  if (a.session.check_numerics) print_numerics_report(stats, session->mode);
  // Dropped or clamped contributions are never silent.
  if (stats.film.changed() > 0 && !a.verbose && !a.quiet)
    std::fprintf(stderr, "[caustica] warning: film dropped %llu NaN/Inf and %llu negative contributions, clamped %llu\n",
                 (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
                 (unsigned long long)stats.film.clamped);
  // Contributions below the film's resolution: each lost less than 2^-45;
  // said when together they could be 0.01% of the image's light.
  if (stats.film.underflow > 0 && !a.quiet) {
    const double share = session->renderer->film().underflow_share(stats.film.underflow);
    if (share > 1e-4)
      std::fprintf(stderr,
                   "[caustica] warning: %llu contributions were below the film's resolution (2^-45 = 2.8e-14) and "
                   "rounded to 0: up to %.3g%% of the image's light; scale the scene's light up\n",
                   (unsigned long long)stats.film.underflow, 100.0 * share);
  }
  if (!a.quiet) {
    std::string accuracy;
    if (monitor.estimate()) accuracy += ", estimated relMSE " + format_error(*monitor.estimate());
    if (monitor.true_rel_mse()) accuracy += ", relMSE against the reference " + format_error(*monitor.true_rel_mse());
    if (monitor.denoised_estimate()) accuracy += "; denoised: estimated relMSE " + format_error(*monitor.denoised_estimate());
    if (monitor.denoised_true_rel_mse())
      accuracy += std::string(monitor.denoised_estimate() ? "," : "; denoised:") + " relMSE against the reference " +
                  format_error(*monitor.denoised_true_rel_mse());
    std::string resumed;
    if (resume) resumed = ", resumed from " + std::to_string(resumed_passes) + " spp in " + a.resume;
    std::fprintf(stderr, "[caustica] wrote %s (%dx%d, %d spp%s) in %.2f s%s\n", a.output.c_str(), image.width,
                 image.height, shown->film().passes(), resumed.c_str(), stats.render_ms / 1e3,
                 accuracy.c_str());
    if (!a.checkpoint.empty())
      std::fprintf(stderr, "[caustica] wrote %s (the render's state at %d spp)\n", a.checkpoint.c_str(),
                   shown->film().passes());
    if (!a.report.empty())
      std::fprintf(stderr, "[caustica] wrote %s (%d measurements, %.1f ms measuring = %.2f%% of the render)%s%s\n",
                   a.report.c_str(), monitor.measurements(), monitor.measurement_seconds() * 1e3,
                   100.0 * monitor.measurement_seconds() / std::max(1e-9, stats.render_ms / 1e3),
                   a.plot.empty() ? "" : " and ", a.plot.c_str());
  }
  return 0;
}

}  // namespace caustica
