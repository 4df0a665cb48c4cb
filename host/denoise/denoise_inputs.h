// What `caustica denoise` reads: a colour image and, optionally, its albedo
// and normal guides, from one EXR's layers or from three files. Apart from
// the denoiser (host/denoise/denoiser.h), so that fuzzing reaches it in
// any build (fuzz/fuzz_denoise_inputs.cpp).
//
// Layers are found by name, as the renderers that write them name them
// (the first that an image has; Blender's view-layer prefix, "ViewLayer.",
// is allowed before any of them):
//   colour: beauty.RGB (caustica's raw film beside a denoised main image),
//           Noisy Image.RGB (Blender), Combined.RGB (Blender), RGB
//   albedo: albedo.RGB (caustica, Mitsuba's albedo AOV), Denoising Albedo.RGB (Blender)
//   normal: normal.XYZ or .RGB (caustica), Denoising Normal.XYZ (Blender),
//           sh_normal.XYZ or nn.XYZ (Mitsuba's AOVs), Normal.XYZ (Blender)
// A guide file of its own (--albedo, --normal) is read as its RGB (or XYZ).
#pragma once

#include <optional>
#include <string>

#include "host/image/image.h"

namespace caustica {

struct DenoiseInputs {
  ImageF colour;
  std::optional<ImageF> albedo, normal;
  std::string colour_layer, albedo_layer, normal_layer;  // what was read ("" for R, G, B)
};

// Throws caustica::Error naming the file and what it lacks: no colour
// layer, a guide of another size, a normal without an albedo.
DenoiseInputs read_denoise_inputs(const std::string& path, const std::string& albedo_path = "",
                                  const std::string& normal_path = "");

}  // namespace caustica
