// caustica command line: render, merge, denoise, devices, bench, generate, sky, diff, plot.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>

#include "host/app/bench.h"
#include "host/app/render_command.h"
#include "host/app/diff.h"
#include "host/app/cli_numbers.h"
#include "host/app/denoise_command.h"
#include "host/app/merge_command.h"
#include "host/app/plot.h"
#include "host/app/session.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/tonemap.h"
#include "host/scene/generate.h"
#include "host/scene/sky_model.h"
#ifdef CAUSTICA_WITH_MPI
#include "host/mpi/mpi_ranks.h"
#endif

using namespace caustica;

namespace {
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

// "rank 1 of 3: " under mpirun with several ranks, else "".
std::string rank_prefix(const RankGroup* ranks) {
  if (!ranks || ranks->size() <= 1) return "";
  return "rank " + std::to_string(ranks->rank()) + " of " + std::to_string(ranks->size()) + ": ";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"caustica: an OpenCL wavefront renderer for the coursework scene format"};
  app.require_subcommand(1);

  RenderArgs render;
  CLI::App* render_cmd = add_render_command(app, render);
  app.add_subcommand("devices", "list OpenCL platforms and devices");
  MergeArgs merge;
  CLI::App* merge_cmd = add_merge_command(app, merge);
  DenoiseArgs denoise;
  CLI::App* denoise_cmd = add_denoise_command(app, denoise);

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
  bench_cmd->add_option("--local-size", bench.session.local_size, "work-group size of every stage launch (default 64)")
      ->check(CLI::Range(1, 1024));
  bench_cmd->add_option_function<std::string>(
      "--bvh", [&](const std::string& q) { bench.session.bvh_quality = parse_bvh_quality(q); },
      "BVH build: spatial (default), sah or fast");
  bench_cmd->add_option_function<std::string>(
      "--caustics", [&](const std::string& m) { bench.session.caustics = parse_caustics_mode(m); },
      "path: the photon pass, auto (default), on or off");

  int shapes = 400;
  bool spheres_only = false;
  uint32_t seed = 1;
  std::string generate_out;
  auto* gen_cmd = app.add_subcommand("generate", "write a benchmark scene like the seed report's Table 1");
  gen_cmd->add_option("--shapes", shapes, "number of shapes")->check(CLI::Range(1, 10000000));
  gen_cmd->add_flag("--spheres-only", spheres_only, "only spheres (the 400_spheres scene)");
  gen_cmd->add_option("--seed", seed, "random seed");
  gen_cmd->add_option("-o,--output", generate_out, "output JSON")->required();

  SkyParams sky;
  std::string sky_out;
  auto* sky_cmd = app.add_subcommand("sky", "write the Preetham sun and sky as an equirectangular image (.pfm, .exr), "
                                            "as a scene's \"environment\": {\"sky\": ...} makes it");
  sky_cmd->add_option("--sun-elevation", sky.sun_elevation, "degrees above the horizon")->check(finite_range(0.5, 90.0));
  sky_cmd->add_option("--sun-azimuth", sky.sun_azimuth, "degrees from +z toward +x")->check(finite_range(-360.0, 360.0));
  sky_cmd->add_option("--turbidity", sky.turbidity, "1.7 (clear) to 10 (hazy)")->check(finite_range(1.7, 10.0));
  sky_cmd->add_option("--width", sky.width, "texels across")->check(CLI::Range(8, 4096));
  sky_cmd->add_option("--height", sky.height, "texels down")->check(CLI::Range(4, 2048));
  sky_cmd->add_option("-o,--output", sky_out, "output image (.pfm or .exr: linear)")->required();

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

  // Under mpirun: the ranks (MPI starts here, and only under a launcher).
  std::unique_ptr<RankGroup> ranks;
#ifdef CAUSTICA_WITH_MPI
  try {
    ranks = MpiRanks::if_launched(&argc, &argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "caustica: error: %s\n", e.what());
    return 1;
  }
#else
  // Started by mpirun without MPI built in, every rank would render the
  // whole image and write the same files.
  if (const char* size = std::getenv("OMPI_COMM_WORLD_SIZE"); size && std::atoi(size) > 1) {
    std::fprintf(stderr, "caustica: error: started by mpirun with %s ranks, but this caustica was built without MPI "
                         "(install libopenmpi-dev and build again: docs/distributed.md)\n", size);
    return 1;
  }
#endif
  render.ranks = ranks.get();
  // A rank that fails ends the others (MPI_Abort): none waits forever in a
  // collective for it.
  auto failed = [&ranks]() -> int {
    if (ranks && ranks->size() > 1) {
      std::fflush(stderr);
      ranks->abort(1);
    }
    return 1;
  };
  // Parsing runs inside the try: option callbacks (--bvh, --exposure...)
  // throw caustica::Error for values they refuse, and an exception escaping
  // main would abort with "terminate called" instead of a message.
  try {
    CLI11_PARSE(app, argc, argv);
    if (app.got_subcommand(render_cmd)) return run_render(render);
    if (app.got_subcommand("devices")) return run_devices();
    if (app.got_subcommand(merge_cmd)) return run_merge(merge);
    if (app.got_subcommand(denoise_cmd)) return run_denoise(denoise);
    if (app.got_subcommand(bench_cmd)) return run_bench(bench);
    if (app.got_subcommand(diff_cmd)) return run_diff(diff);
    if (app.got_subcommand(plot_cmd)) {
      plot_error_reports(plot_reports, plot_out);
      return 0;
    }
    if (app.got_subcommand(sky_cmd)) {
      if (!is_hdr_path(sky_out)) throw Error(sky_out + ": expected a .pfm or .exr output (the sky is linear radiance)");
      check_output_image_path(sky_out);
      write_image(sky_out, preetham_sky(sky), DisplaySettings{});
      return 0;
    }
    if (app.got_subcommand(gen_cmd)) {
      std::ofstream out(generate_out);
      if (!out) throw Error(generate_out + ": cannot open for writing");
      out << generate_table1_scene(shapes, !spheres_only, seed).dump(2) << "\n";
      out.close();  // flushes: a full disk shows here
      if (!out) throw Error(generate_out + ": write failed (disk full?)");
      return 0;
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "caustica: error: %s%s\n", rank_prefix(ranks.get()).c_str(), e.what());
    return failed();
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "caustica: OpenCL error: %s%s (%s)\n", rank_prefix(ranks.get()).c_str(), e.what(),
                 cl_error_name(e.err()).c_str());
    return failed();
  } catch (const std::bad_alloc&) {
    // Every input size is bounded (host/limits.h); this is the machine's own limit.
    std::fprintf(stderr, "caustica: error: %sout of memory (std::bad_alloc): this machine cannot hold the request\n",
                 rank_prefix(ranks.get()).c_str());
    return failed();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "caustica: error: %s%s\n", rank_prefix(ranks.get()).c_str(), e.what());
    return failed();
  }
  return 0;
}
