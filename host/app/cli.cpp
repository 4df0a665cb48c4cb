#include "host/app/cli.h"

#include <cstdio>
#include <fstream>
#include <iostream>

#include "host/app/cli_numbers.h"
#include "host/app/plot.h"
#include "host/app/session.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/scene/features.h"
#include "host/scene/generate.h"
#include "host/write_file.h"

namespace caustica {

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

}  // namespace

Cli::Cli()
    : owned_app_(std::make_unique<CLI::App>("caustica: an OpenCL wavefront renderer for the coursework scene format")),
      app(*owned_app_) {}

Cli::~Cli() = default;

int parse_command_line(Cli& cli, int argc, const char* const* argv) {
  try {
    cli.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.app.exit(e);
  }
  return -1;
}

std::unique_ptr<Cli> make_cli() {
  auto cli = std::make_unique<Cli>();
  Cli& c = *cli;
  CLI::App& app = c.app;
  app.require_subcommand(1);

  c.render_cmd = add_render_command(app, c.render);
  c.devices_cmd = app.add_subcommand("devices", "list OpenCL platforms and devices");
  c.merge_cmd = add_merge_command(app, c.merge);
  c.denoise_cmd = add_denoise_command(app, c.denoise);

  BenchArgs& bench = c.bench;
  auto* bench_cmd = c.bench_cmd = app.add_subcommand("bench", "time BVH build, kernel build, ray throughput and rendering");
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

  auto* gen_cmd = c.generate_cmd = app.add_subcommand("generate", "write a benchmark scene like the seed report's Table 1");
  gen_cmd->add_option("--shapes", c.generate.shapes, "number of shapes")->check(CLI::Range(1, 10000000));
  gen_cmd->add_flag("--spheres-only", c.generate.spheres_only, "only spheres (the 400_spheres scene)");
  gen_cmd->add_option("--seed", c.generate.seed, "random seed");
  gen_cmd->add_option("-o,--output", c.generate.output, "output JSON")->required();

  SkyParams& sky = c.sky.params;
  auto* sky_cmd = c.sky_cmd = app.add_subcommand("sky", "write the Preetham sun and sky as an equirectangular image (.pfm, .exr), "
                                            "as a scene's \"environment\": {\"sky\": ...} makes it");
  sky_cmd->add_option("--sun-elevation", sky.sun_elevation, "degrees above the horizon")->check(finite_range(0.5, 90.0));
  sky_cmd->add_option("--sun-azimuth", sky.sun_azimuth, "degrees from +z toward +x")->check(finite_range(-360.0, 360.0));
  sky_cmd->add_option("--turbidity", sky.turbidity, "1.7 (clear) to 10 (hazy)")->check(finite_range(1.7, 10.0));
  sky_cmd->add_option("--width", sky.width, "texels across")->check(CLI::Range(8, 4096));
  sky_cmd->add_option("--height", sky.height, "texels down")->check(CLI::Range(4, 2048));
  sky_cmd->add_option("-o,--output", c.sky.output, "output image (.pfm or .exr: linear)")->required();

  DiffArgs& diff = c.diff;
  auto* diff_cmd = c.diff_cmd = app.add_subcommand("diff", "error of image A against reference B: MSE, relMSE, MAE, PSNR");
  diff_cmd->add_option("image", diff.image_path, "image to judge (.pfm .exr linear; .png .ppm ... 8-bit)")->required();
  diff_cmd->add_option("reference", diff.reference_path, "reference image, same size")->required();
  diff_cmd->add_option("--heatmap", diff.heatmap_path, "also draw the per-pixel error with a colour bar (.png)");
  diff_cmd->add_option("--metric", diff.metric, "error the heatmap shows: relmse (default), mse or mae");

  auto* plot_cmd = c.plot_cmd = app.add_subcommand("plot", "draw error against render time from error reports (CSV)");
  plot_cmd->add_option("reports", c.plot.reports, "error report CSV files")->required();
  plot_cmd->add_option("-o,--output", c.plot.output, "output figure (.png or .svg)")->required();

  return cli;
}

void check_command_options(Cli& c) {
  if (c.render_cmd->parsed()) check_render_options(c.render);
  if (c.sky_cmd->parsed()) {
    if (!is_hdr_path(c.sky.output))
      throw Error(c.sky.output + ": expected a .pfm or .exr output (the sky is linear radiance)");
    check_output_image_path(c.sky.output);
  }
}

int run_command(Cli& c) {
  if (c.render_cmd->parsed()) return run_render(c.render);
  if (c.devices_cmd->parsed()) return run_devices();
  if (c.merge_cmd->parsed()) return run_merge(c.merge);
  if (c.denoise_cmd->parsed()) return run_denoise(c.denoise);
  if (c.bench_cmd->parsed()) return run_bench(c.bench);
  if (c.diff_cmd->parsed()) return run_diff(c.diff);
  if (c.plot_cmd->parsed()) {
    plot_error_reports(c.plot.reports, c.plot.output);
    return 0;
  }
  if (c.sky_cmd->parsed()) {
    check_command_options(c);
    write_image(c.sky.output, preetham_sky(c.sky.params), DisplaySettings{});
    return 0;
  }
  if (c.generate_cmd->parsed()) {
    write_output_file(c.generate.output,
                      generate_table1_scene(c.generate.shapes, !c.generate.spheres_only, c.generate.seed).dump(2) +
                          "\n",
                      "scene");
    return 0;
  }
  return 0;
}

}  // namespace caustica
