#include "host/app/film_outputs.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace caustica {
namespace {

void add_rgb(std::vector<ExrPlane>& planes, const std::string& layer, const ImageF& image, float scale,
             const char* channels = "RGB") {
  const size_t n = image.pixel_count();
  for (int c = 0; c < 3; ++c) {
    ExrPlane plane{layer.empty() ? std::string(1, channels[c]) : layer + "." + channels[c], std::vector<float>(n)};
    for (size_t i = 0; i < n; ++i) plane.values[i] = image.rgb[3 * i + c] * scale;
    planes.push_back(std::move(plane));
  }
}

void write_single(const std::string& path, int width, int height, std::vector<ExrPlane> planes) {
  write_exr_planes(path, width, height, std::move(planes));
}

}  // namespace

std::vector<ExrPlane> film_pass_planes(const FilmPasses& passes, const std::vector<uint32_t>& spp,
                                       float exposure_scale, const ImageF* main_image) {
  std::vector<ExrPlane> planes;
  add_rgb(planes, "", main_image ? *main_image : passes.colour, exposure_scale);
  if (main_image) add_rgb(planes, "beauty", passes.colour, exposure_scale);
  if (passes.aux) {
    add_rgb(planes, "albedo", passes.aux->albedo, 1.0f);
    add_rgb(planes, "normal", passes.aux->normal, 1.0f, "XYZ");
    planes.push_back({"depth.Z", passes.aux->depth});
  }
  if (!passes.variance.empty()) {
    ExrPlane variance{"variance.Y", passes.variance};
    for (float& v : variance.values) v *= exposure_scale * exposure_scale;
    planes.push_back(std::move(variance));
  }
  // Counts are exact as float up to 2^24 samples per pixel.
  planes.push_back({"spp", std::vector<float>(spp.begin(), spp.end())});
  return planes;
}

ImageF write_film_outputs(const FilmOutputOptions& options, const Film& film) {
  // A plain image needs the mean alone: no passes, no variance read back.
  if (!options.denoiser && options.aov_dir.empty() && lower_extension(options.output) != ".exr") {
    ImageF image = film.mean();
    write_image(options.output, image, options.display);
    return image;
  }
  const FilmPasses passes = read_film_passes(film, options.guides);
  ImageF denoised;
  if (options.denoiser) {
    const auto t0 = std::chrono::steady_clock::now();
    denoised = denoise_passes(*options.denoiser, passes);
    if (options.verbose)
      std::fprintf(stderr, "[caustica] denoised at %d spp in %.3f s; guides %s (their estimated relMSE %s)\n",
                   film.passes(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                   !passes.aux ? "none" : guide_mode_name(passes.guides),
                   passes.guide_noise ? std::to_string(*passes.guide_noise).c_str() : "not measured");
  }
  write_pass_outputs(options, film.width(), film.height(), passes, film.pixel_spp(),
                     options.denoiser ? &denoised : nullptr);
  return options.denoiser ? denoised : passes.colour;
}

void write_pass_outputs(const FilmOutputOptions& options, int w, int h, const FilmPasses& passes,
                        const std::vector<uint32_t>& spp, const ImageF* denoised) {
  const ImageF& main_image = denoised ? *denoised : passes.colour;
  const float scale = options.display.exposure_scale;
  if (lower_extension(options.output) == ".exr")
    write_exr_planes(options.output, w, h, film_pass_planes(passes, spp, scale, denoised));
  else
    write_image(options.output, main_image, options.display);
  if (!options.aov_dir.empty()) {
    const std::filesystem::path dir(options.aov_dir);
    std::vector<ExrPlane> one;
    auto rgb = [&](const char* name, const ImageF& image, float s) {
      one.clear();
      add_rgb(one, "", image, s);
      write_single((dir / name).string(), w, h, std::move(one));
    };
    auto grey = [&](const char* name, std::vector<float> values) {
      write_single((dir / name).string(), w, h, {{"Y", std::move(values)}});
    };
    rgb("beauty.exr", passes.colour, scale);
    if (denoised) rgb("denoised.exr", *denoised, scale);
    if (passes.aux) {
      rgb("albedo.exr", passes.aux->albedo, 1.0f);
      rgb("normal.exr", passes.aux->normal, 1.0f);
      grey("depth.exr", passes.aux->depth);
    }
    if (!passes.variance.empty()) {
      std::vector<float> v = passes.variance;
      for (float& x : v) x *= scale * scale;
      grey("variance.exr", std::move(v));
    }
    grey("spp.exr", std::vector<float>(spp.begin(), spp.end()));
  }
}

}  // namespace caustica
