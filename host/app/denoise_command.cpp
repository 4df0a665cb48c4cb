#include "host/app/denoise_command.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "host/denoise/denoise_inputs.h"
#include "host/denoise/denoiser.h"
#include "host/error.h"
#include "host/image/image_io.h"

namespace caustica {

CLI::App* add_denoise_command(CLI::App& app, DenoiseArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "denoise", "denoise a rendered EXR (colour with albedo and normal layers, or three files) with Open Image Denoise");
  cmd->add_option("input", a.input, "linear .exr (with layers) or .pfm image")->required();
  cmd->add_option("-o,--output", a.output, "the denoised image (.exr keeps the input's colour and guides as layers; "
                                           ".pfm, or .png/.ppm tone mapped as linear)")
      ->required();
  cmd->add_option("--albedo", a.albedo, "the albedo guide as a file of its own (.exr/.pfm)");
  cmd->add_option("--normal", a.normal, "the normal guide as a file of its own (.exr/.pfm; needs an albedo)");
  cmd->add_option("--quality", a.quality, "fast | balanced | high (default)")
      ->check(CLI::IsMember({"fast", "balanced", "high"}));
  cmd->add_option("--threads", a.threads, "CPU threads (default: every core)")->check(CLI::Range(1, 1024));
  cmd->add_flag("--noisy-guides", a.noisy_guides,
                "the guides are noisy (depth of field, few samples): OIDN's filter for noisy guides");
  cmd->add_flag("--prefilter-guides", a.prefilter_guides,
                "the guides are noisy: denoise them first, then use them as clean (OIDN's best quality, 3x the time)");
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_denoise(const DenoiseArgs& a) {
  check_output_image_path(a.output);
  if (!Denoiser::available()) throw Error("denoise: " + Denoiser::missing_message());
  const DenoiseInputs in = read_denoise_inputs(a.input, a.albedo, a.normal);
  DenoiserOptions options;
  options.quality = parse_denoise_quality(a.quality);
  options.threads = a.threads;
  const Denoiser denoiser(options);
  DenoiseGuides guides;
  if (in.albedo) guides.albedo = &*in.albedo;
  if (in.normal) guides.normal = &*in.normal;
  guides.clean = !a.noisy_guides && !a.prefilter_guides;
  guides.prefilter = a.prefilter_guides;
  const auto t0 = std::chrono::steady_clock::now();
  const ImageF denoised = denoiser.denoise(in.colour, guides);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (lower_extension(a.output) == ".exr") {
    std::vector<ExrPlane> planes;
    auto add = [&](const std::string& layer, const ImageF& image, const char* channels) {
      for (int c = 0; c < 3; ++c) {
        ExrPlane p{layer.empty() ? std::string(1, channels[c]) : layer + "." + channels[c],
                   std::vector<float>(image.pixel_count())};
        for (size_t i = 0; i < image.pixel_count(); ++i) p.values[i] = image.rgb[3 * i + c];
        planes.push_back(std::move(p));
      }
    };
    add("", denoised, "RGB");
    add("beauty", in.colour, "RGB");
    if (in.albedo) add("albedo", *in.albedo, "RGB");
    if (in.normal) add("normal", *in.normal, "XYZ");
    write_exr_planes(a.output, denoised.width, denoised.height, std::move(planes));
  } else {
    write_image(a.output, denoised, DisplaySettings{});
  }
  if (!a.quiet) {
    std::string used = in.albedo ? "albedo (" + in.albedo_layer + ")" : std::string("no guides: colour alone");
    if (in.normal) used += " and normal (" + in.normal_layer + ")";
    std::fprintf(stderr, "[caustica] denoised %s (%dx%d, colour %s, %s) with %s in %.3f s: wrote %s\n",
                 a.input.c_str(), denoised.width, denoised.height,
                 in.colour_layer.empty() ? "R, G, B" : in.colour_layer.c_str(), used.c_str(),
                 denoiser.description().c_str(), seconds, a.output.c_str());
  }
  return 0;
}

}  // namespace caustica
