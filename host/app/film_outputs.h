// What a path-mode render writes from its film (issue 37): the main image
// (denoised with --denoise), and where they can go, the passes a
// compositor or denoiser takes. An .exr output holds them as layers named
// as Blender's compositor reads them:
//   R, G, B              the main image (denoised with --denoise)
//   beauty.R/G/B         the raw film, when the main image is denoised
//   albedo.R/G/B         the first rough surface's albedo (through mirrors and smooth glass)
//   normal.X/Y/Z         its shading normal (world space, toward the camera)
//   depth.Z              the camera ray's distance to the first hit (0: none)
//   variance.Y           each pixel's estimated variance (the error estimate's)
//   spp                  each pixel's samples
// Colour and variance are scaled by the exposure (variance by its square),
// as every HDR output is. --aov-dir DIR writes each as its own .exr
// (beauty, denoised, albedo, normal, depth, variance, spp) for tools that
// take one image; one-channel passes as a "Y" channel.
#pragma once

#include <string>
#include <vector>

#include "host/denoise/film_denoise.h"
#include "host/image/image_io.h"

namespace caustica {

struct FilmOutputOptions {
  std::string output;          // -o: the extension picks the format
  std::string aov_dir;         // --aov-dir: "" none
  DisplaySettings display;     // 8-bit outputs' tone curve; exposure_scale scales HDR ones
  const Denoiser* denoiser = nullptr;  // --denoise: the main image is denoised
  bool verbose = false;                // -v: say how the guides were judged and what denoising took
  GuideMode guides = GuideMode::Clean;  // how the guides are handed over (host/denoise/film_denoise.h)
};

// Every pass the film holds as the EXR's planes: R, G, B are `main_image`
// (the denoised image, with the film's colour as "beauty") or, when null,
// the film's colour.
std::vector<ExrPlane> film_pass_planes(const FilmPasses& passes, const std::vector<uint32_t>& spp,
                                       float exposure_scale, const ImageF* main_image);
// Writes the outputs for `film` (path mode); returns the main image.
ImageF write_film_outputs(const FilmOutputOptions& options, const Film& film);
// What write_film_outputs writes once the film's passes are read (and,
// given `denoised`, denoised: options.denoiser is not used here): the
// Python module's Render.save, which keeps the passes and not the film.
void write_pass_outputs(const FilmOutputOptions& options, int width, int height, const FilmPasses& passes,
                        const std::vector<uint32_t>& spp, const ImageF* denoised);

}  // namespace caustica
