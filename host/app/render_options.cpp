// `caustica render`'s options: their definitions (CLI11) and the checks of
// their values and combinations, made before anything is read (a typo in
// one must not cost a render). The run itself: render_command.cpp.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

#include "host/app/cli_numbers.h"
#include "host/app/render_command.h"
#include "host/denoise/denoiser.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/limits.h"

namespace caustica {
namespace {

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

// --plot and --spp-map: figures drawn through gnuplot, which writes these two.
void check_figure_path(const std::string& option, const std::string& path) {
  if (path.empty()) return;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".png" && ext != ".svg") throw Error(option + " " + path + ": expected a .png or .svg file name");
  check_output_dir(option, path);
}

// The state file --checkpoint names: its folder, its kind, and no other file
// of the render.
void check_checkpoint_path(const RenderArgs& a) {
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

// --passes START:END: the session renders passes [START, END), sampled as
// those passes of a full render.
void take_pass_range(RenderArgs& a) {
  const auto [first, end] = parse_pass_range(a.passes);
  if (a.session.spp > 0) throw Error("--passes " + a.passes + " and --spp: give one (--passes ends at END)");
  if (a.session.time_limit_s > 0.0 || a.target_error > 0.0)
    throw Error("--passes " + a.passes + ": a render of a fixed set of passes takes no --time or --target-error");
  // Adaptive sampling places each wave by the error estimate of every pass
  // before it: a range rendered alone cannot know its allocation.
  if (a.session.adaptive)
    throw Error("--passes " + a.passes + ": adaptive sampling plans each wave from the error of the whole film, "
                "which a render of some of its passes does not hold (each wave's allocation depends on every pass before "
                "it, from pass 0): add --no-adaptive and `caustica merge` the "
                "parts' states, or render on mpirun's ranks, which keep adaptive sampling (docs/distributed.md)");
  a.session.first_pass = first;
  a.session.spp = end;
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
                         "path: stop when the estimated relMSE's 90% upper bound reaches E, not the point estimate, which "
                         "reads low where light is rare (with --time/--spp: whichever first)")
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
  render_cmd->add_option_function<std::string>(
      "--light-sampler", [&a](const std::string& s) { a.session.light_sampler = parse_light_sampler(s); },
      "path: how next-event estimation picks a light: auto (default: the light tree above 3 lights), tree, power "
      "(one CDF by power) or uniform");
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
  check_figure_path("--plot", a.plot);
  check_figure_path("--spp-map", a.spp_map);
  if (!a.plot.empty() && a.report.empty()) throw Error("--plot " + a.plot + ": needs --report (the plot is drawn from it)");
  if (a.target_error > 0.0 && a.no_error_estimate)
    throw Error("--target-error needs the error estimate that --no-error-estimate leaves out");
  if (a.checkpoint_every_s && a.checkpoint.empty())
    throw Error("--checkpoint-every needs --checkpoint (the file the state is written to)");
  if (!a.checkpoint.empty()) check_checkpoint_path(a);
  if (a.denoise && !Denoiser::available()) throw Error("--denoise: " + Denoiser::missing_message());
  if (!a.aov_dir.empty()) check_output_dir("--aov-dir", a.aov_dir);  // DIR's parent exists (DIR is made)
  // The film's aux passes: what the denoiser and an .exr's layers take.
  a.session.aux_passes = a.denoise || !a.aov_dir.empty() || lower_extension(a.output) == ".exr";
  const bool distributed = a.ranks && a.ranks->size() > 1;
  if (distributed) check_distributed_options(a);
  if (!a.passes.empty()) take_pass_range(a);
}

}  // namespace caustica
