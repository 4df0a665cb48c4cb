// caustica command line: render, devices, bench, generate, diff, plot.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>

#include "host/app/bench.h"
#include "host/app/diff.h"
#include "host/app/plot.h"
#include "host/app/session.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/scene/generate.h"

using namespace caustica;

namespace {

// Progress on stderr: a rewritten line on a terminal, one line a second
// otherwise; silent for renders that finish within a second.
class ProgressReporter {
 public:
  explicit ProgressReporter(bool enabled) : enabled_(enabled), tty_(isatty(2)) {}
  void update(const PassProgress& p) {
    if (!enabled_) return;
    const double s = seconds();
    const double samples = double(p.pixels_total) * p.pass + double(p.pixels_done);  // pixel samples done
    const bool open_ended = p.passes == std::numeric_limits<int>::max();
    const double total = double(p.pixels_total) * p.passes;
    const uint64_t rays = p.stats ? p.stats->rays() : 0;
    if (s < 1.0 || (!tty_ && s - last_ < 1.0 && samples < total)) return;
    last_ = s;
    // Time left: to the sample target at the current rate, or to the time
    // limit, whichever comes first.
    double left = samples > 0 && !open_ended ? s * (total - samples) / samples : 1e300;
    if (p.time_limit_s > 0.0) left = std::min(left, std::max(0.0, p.time_limit_s - p.seconds));
    char target[32];
    if (open_ended) std::snprintf(target, sizeof target, "%s", "-");
    else std::snprintf(target, sizeof target, "%d", p.passes);
    std::fprintf(stderr, "%s[caustica] %.2f/%s spp, %.3g samples/s, %.2f Mrays/s, %.1f s elapsed, %.1f s left%s",
                 tty_ ? "\r" : "", samples / double(p.pixels_total), target, samples / s, rays / s * 1e-6, s,
                 left < 1e299 ? left : 0.0, tty_ ? "" : "\n");
    printed_ = true;
  }
  void finish() {
    if (printed_ && tty_) std::fprintf(stderr, "\n");
  }

 private:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool enabled_, tty_, printed_ = false;
  double last_ = 0.0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

int run_devices() {
  const auto devices = list_devices();
  if (devices.empty()) {
    std::cout << "no OpenCL devices (Debian: apt-get install pocl-opencl-icd)\n";
    return 1;
  }
  const DeviceInfo chosen = select_device("");
  for (const auto& d : devices) {
    std::printf("[%d] %-4s %-48s platform: %s | %u compute units | %s | %.1f GiB%s\n", d.index, d.type.c_str(),
                d.name.c_str(), d.platform_name.c_str(), d.compute_units, d.device_version.c_str(),
                d.global_mem_bytes / 1073741824.0, d.index == chosen.index ? "  (default)" : "");
  }
  return 0;
}

struct RenderArgs {
  SessionOptions session;
  std::string mode, output, tonemap;  // tonemap default: linear, or aces in path mode
  std::optional<float> exposure;
  std::optional<float> gamma;  // default: kCourseworkDisplayGamma, or kPathDisplayGamma in path mode
  bool verbose = false, quiet = false;
  double write_every_s = 0.0;  // path: also write the image while rendering
};

int run_render(RenderArgs& a) {
  a.session.mode = parse_render_mode(a.mode);
  if (a.output.empty()) a.output = std::filesystem::path(a.session.scene_path).stem().string() + ".png";
  const auto session = prepare_session(a.session);
  const Scene& scene = session->scene;
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
  double last_write = 0.0;
  const ImageF image = session->renderer->render(
      &stats, [&](const PassProgress& p) { progress.update(p); },
      [&](const Film& film, double seconds) {
        if (a.write_every_s <= 0.0 || seconds - last_write < a.write_every_s) return;
        last_write = seconds;
        write_image(a.output, film.mean(), display);
      });
  progress.finish();
  write_image(a.output, image, display);
  if (a.verbose) {
    const uint64_t rays = stats.camera_rays + stats.secondary_rays + stats.shadow_rays;
    std::fprintf(stderr, "[caustica] render: %.1f ms, %dx%d, %llu camera + %llu secondary + %llu shadow rays (%.2f Mrays/s)%s\n",
                 stats.render_ms, image.width, image.height, (unsigned long long)stats.camera_rays,
                 (unsigned long long)stats.secondary_rays, (unsigned long long)stats.shadow_rays,
                 rays / (stats.render_ms * 1e3), stats.chunk_retries ? " (queue overflow: chunks split)" : "");
    std::fprintf(stderr, "[caustica] host traffic: %llu kernel launches, %llu blocking transfers; film scale 2^%d\n",
                 (unsigned long long)stats.launches, (unsigned long long)stats.blocking_transfers,
                 int(std::log2(session->renderer->film().params().scale)));
    std::fprintf(stderr, "[caustica] film: %d passes; dropped %llu NaN/Inf and %llu negative contributions, clamped %llu\n",
                 stats.passes, (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
                 (unsigned long long)stats.film.clamped);
  }
  // Dropped or clamped contributions are never silent.
  if (stats.film.total() > 0 && !a.verbose && !a.quiet)
    std::fprintf(stderr, "[caustica] warning: film dropped %llu NaN/Inf and %llu negative contributions, clamped %llu\n",
                 (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
                 (unsigned long long)stats.film.clamped);
  if (!a.quiet) std::fprintf(stderr, "[caustica] wrote %s (%dx%d) in %.2f s\n", a.output.c_str(), image.width,
                             image.height, stats.render_ms / 1e3);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"caustica: an OpenCL wavefront renderer for the coursework scene format"};
  app.require_subcommand(1);

  RenderArgs render;
  auto* render_cmd = app.add_subcommand("render", "render a scene to an image (.ppm .png .pfm .exr)");
  render_cmd->add_option("scene", render.session.scene_path, "scene JSON file")->required();
  render_cmd->add_option("-o,--output", render.output, "output image; the extension picks the format");
  render_cmd->add_option("--mode", render.mode, "binary | phong | path (default: the scene's rendermode)");
  render_cmd->add_option("--width", render.session.width, "image width (keeps the camera's aspect unless --height)");
  render_cmd->add_option("--height", render.session.height, "image height");
  render_cmd->add_option("--tonemap", render.tonemap, "linear | reinhard | aces (default linear; aces in path mode)");
  render_cmd->add_option("--exposure", render.exposure, "exposure in stops (default: the camera's \"exposure\")");
  render_cmd->add_option("--gamma", render.gamma,
                         "display gamma of 8-bit outputs (default 1.22 as the coursework handout; 2.2 in path mode)");
  render_cmd->add_option("--device", render.session.device,
                         "OpenCL device: index, name substring, cpu or gpu (env CAUSTICA_DEVICE)");
  render_cmd->add_flag("--no-cache", [&](int64_t) { render.session.use_kernel_cache = false; },
                       "rebuild kernels instead of loading cached binaries");
  render_cmd->add_option_function<std::string>(
      "--bvh", [&](const std::string& q) { render.session.bvh_quality = parse_bvh_quality(q); },
      "BVH build: spatial (SBVH, default), sah, or fast for huge scenes");
  render_cmd->add_flag("--strict", render.session.strict, "unknown scene keys are errors, not warnings");
  render_cmd->add_option("--spp", render.session.spp, "path: samples per pixel (default 64)")->check(CLI::PositiveNumber);
  render_cmd->add_option("--seed", render.session.seed, "path: seed of the sample sequences (default 0)");
  render_cmd->add_option("--time", render.session.time_limit_s,
                         "path: stop after the pass that reaches SECONDS (with --spp: whichever comes first)")
      ->check(CLI::PositiveNumber);
  render_cmd->add_option("--write-every", render.write_every_s, "path: also write the image every SECONDS")
      ->check(CLI::PositiveNumber);
  render_cmd->add_option_function<std::string>(
      "--sampler",
      [&](const std::string& s) {
        if (s != "sobol" && s != "independent") throw CLI::ValidationError("--sampler", "expected sobol or independent");
        render.session.independent_samples = s == "independent";
      },
      "path: sobol (Owen-scrambled Sobol-Burley, default) or independent");
  render_cmd->add_flag("-v,--verbose", render.verbose, "print features, build, BVH and render times");
  render_cmd->add_flag("-q,--quiet", render.quiet, "print nothing but errors");

  app.add_subcommand("devices", "list OpenCL platforms and devices");

  BenchArgs bench;
  auto* bench_cmd = app.add_subcommand("bench", "time BVH build, kernel build, ray throughput and rendering");
  bench_cmd->add_option("scene", bench.session.scene_path, "scene JSON file")->required();
  bench_cmd->add_option("--mode", bench.mode, "binary | phong | path");
  bench_cmd->add_option("--spp", bench.session.spp, "path: samples per pixel of each timed render (default 16)")
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--width", bench.session.width, "image width");
  bench_cmd->add_option("--height", bench.session.height, "image height");
  bench_cmd->add_option("--repetitions", bench.repetitions, "timed repetitions (median)")->check(CLI::PositiveNumber);
  bench_cmd->add_option("--device", bench.session.device, "OpenCL device");
  bench_cmd->add_option_function<std::string>(
      "--bvh", [&](const std::string& q) { bench.session.bvh_quality = parse_bvh_quality(q); },
      "BVH build: spatial (default), sah or fast");

  int shapes = 400;
  bool spheres_only = false;
  uint32_t seed = 1;
  std::string generate_out;
  auto* gen_cmd = app.add_subcommand("generate", "write a benchmark scene like the seed report's Table 1");
  gen_cmd->add_option("--shapes", shapes, "number of shapes")->check(CLI::Range(1, 10000000));
  gen_cmd->add_flag("--spheres-only", spheres_only, "only spheres (the 400_spheres scene)");
  gen_cmd->add_option("--seed", seed, "random seed");
  gen_cmd->add_option("-o,--output", generate_out, "output JSON")->required();

  DiffArgs diff;
  auto* diff_cmd = app.add_subcommand("diff", "error of image A against reference B: MSE, relMSE, MAE, PSNR");
  diff_cmd->add_option("image", diff.image_path, "image to judge (.pfm .exr linear; .png .ppm ... 8-bit)")->required();
  diff_cmd->add_option("reference", diff.reference_path, "reference image, same size")->required();
  diff_cmd->add_option("--heatmap", diff.heatmap_path, "also draw the per-pixel error with a colour bar (.png)");
  diff_cmd->add_option("--metric", diff.metric, "error the heatmap shows: relmse (default), mse or mae");

  std::vector<std::string> plot_reports;
  std::string plot_out;
  auto* plot_cmd = app.add_subcommand("plot", "draw error against render time from error reports (CSV)");
  plot_cmd->add_option("reports", plot_reports, "error report CSV files")->required();
  plot_cmd->add_option("-o,--output", plot_out, "output figure (.png or .svg)")->required();

  CLI11_PARSE(app, argc, argv);
  try {
    if (app.got_subcommand(render_cmd)) return run_render(render);
    if (app.got_subcommand("devices")) return run_devices();
    if (app.got_subcommand(bench_cmd)) return run_bench(bench);
    if (app.got_subcommand(diff_cmd)) return run_diff(diff);
    if (app.got_subcommand(plot_cmd)) {
      plot_error_reports(plot_reports, plot_out);
      return 0;
    }
    if (app.got_subcommand(gen_cmd)) {
      std::ofstream out(generate_out);
      if (!out) throw Error(generate_out + ": cannot open for writing");
      out << generate_table1_scene(shapes, !spheres_only, seed).dump(2) << "\n";
      return 0;
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "caustica: error: %s\n", e.what());
    return 1;
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "caustica: OpenCL error: %s (%s)\n", e.what(), cl_error_name(e.err()).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "caustica: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
