#include "host/denoise/denoise_inputs.h"

#include <cmath>
#include <vector>

#include "host/error.h"
#include "host/image/image_io.h"

namespace caustica {
namespace {

struct Layer {
  std::string name;  // the full prefix as found (e.g. "ViewLayer.Denoising Albedo"), "" for R, G, B
  std::string channels[3];
};

// The first of `layers` (each with either channel set) that `names` holds.
std::optional<Layer> find_layer(const std::vector<std::string>& names, const std::vector<std::string>& layers,
                                const std::vector<std::string>& sets) {
  auto has = [&](const std::string& n) {
    for (const std::string& x : names)
      if (x == n) return true;
    return false;
  };
  for (const std::string& layer : layers)
    for (const std::string& set : sets) {
      // the layer itself, or any "<view layer>.<layer>"
      std::vector<std::string> prefixes{layer};
      for (const std::string& n : names) {
        const std::string tail = layer.empty() ? std::string(1, set[0]) : layer + "." + set[0];
        if (n.size() > tail.size() + 1 && n.compare(n.size() - tail.size(), tail.size(), tail) == 0 &&
            n[n.size() - tail.size() - 1] == '.')
          prefixes.push_back(n.substr(0, n.size() - tail.size() - 1) + (layer.empty() ? "" : "." + layer));
      }
      for (const std::string& prefix : prefixes) {
        Layer l{prefix, {}};
        bool all = true;
        for (int c = 0; c < 3; ++c) {
          l.channels[c] = prefix.empty() ? std::string(1, set[c]) : prefix + "." + set[c];
          all = all && has(l.channels[c]);
        }
        if (all) return l;
      }
    }
  return std::nullopt;
}

ImageF read_layer(const std::string& path, const Layer& layer, int* width, int* height) {
  ImageF image;
  for (int c = 0; c < 3; ++c) {
    int w = 0, h = 0;
    const std::vector<float> plane = read_exr_channel(path, layer.channels[c], &w, &h);
    if (c == 0) {
      *width = w;
      *height = h;
      image = ImageF(w, h);
    }
    if (plane.size() != image.pixel_count())
      throw Error(path + ": channel " + layer.channels[c] + " is not the size of " + layer.channels[0]);
    for (size_t i = 0; i < plane.size(); ++i) image.rgb[3 * i + c] = plane[i];
  }
  return image;
}

// A guide from a file of its own: its RGB or XYZ.
ImageF read_guide_file(const std::string& path, const char* what, const std::vector<std::string>& layers) {
  if (lower_extension(path) != ".exr") {
    if (lower_extension(path) == ".pfm") return read_pfm(path);
    throw Error(std::string("--") + what + " " + path + ": expected an .exr or .pfm image");
  }
  const std::vector<std::string> names = read_exr_channel_names(path);
  const std::optional<Layer> layer = find_layer(names, layers, {"RGB", "XYZ"});
  if (!layer) throw Error(std::string("--") + what + " " + path + ": no R, G, B (or X, Y, Z) channels");
  int w = 0, h = 0;
  return read_layer(path, *layer, &w, &h);
}

void check_size(const std::string& path, const char* what, const ImageF& guide, const ImageF& colour) {
  if (guide.width != colour.width || guide.height != colour.height)
    throw Error(path + ": the " + what + " is " + std::to_string(guide.width) + "x" + std::to_string(guide.height) +
                ", the colour " + std::to_string(colour.width) + "x" + std::to_string(colour.height));
}

const std::vector<std::string> kColourLayers{"beauty", "Noisy Image", "Combined", ""};
const std::vector<std::string> kAlbedoLayers{"albedo", "Denoising Albedo"};
const std::vector<std::string> kNormalLayers{"normal", "Denoising Normal", "sh_normal", "nn", "Normal"};

}  // namespace

DenoiseInputs read_denoise_inputs(const std::string& path, const std::string& albedo_path,
                                  const std::string& normal_path) {
  if (lower_extension(path) != ".exr" && lower_extension(path) != ".pfm")
    throw Error(path + ": expected a linear .exr (with layers) or .pfm image");
  DenoiseInputs in;
  std::vector<std::string> names;
  if (lower_extension(path) == ".pfm") {
    in.colour = read_pfm(path);
  } else {
    names = read_exr_channel_names(path);
    const std::optional<Layer> colour = find_layer(names, kColourLayers, {"RGB"});
    if (!colour)
      throw Error(path + ": no colour channels (R, G, B, or a beauty, Combined or Noisy Image layer's)");
    int w = 0, h = 0;
    in.colour = read_layer(path, *colour, &w, &h);
    in.colour_layer = colour->name;
  }
  if (in.colour.empty()) throw Error(path + ": an empty image");
  if (!albedo_path.empty()) {
    in.albedo = read_guide_file(albedo_path, "albedo", {""});
    in.albedo_layer = albedo_path;
  } else if (!names.empty()) {
    if (const auto layer = find_layer(names, kAlbedoLayers, {"RGB"})) {
      int w = 0, h = 0;
      in.albedo = read_layer(path, *layer, &w, &h);
      in.albedo_layer = layer->name;
    }
  }
  if (!normal_path.empty()) {
    in.normal = read_guide_file(normal_path, "normal", {""});
    in.normal_layer = normal_path;
  } else if (!names.empty()) {
    if (const auto layer = find_layer(names, kNormalLayers, {"XYZ", "RGB"})) {
      int w = 0, h = 0;
      in.normal = read_layer(path, *layer, &w, &h);
      in.normal_layer = layer->name;
    }
  }
  if (in.albedo) check_size(albedo_path.empty() ? path : albedo_path, "albedo", *in.albedo, in.colour);
  if (in.normal) check_size(normal_path.empty() ? path : normal_path, "normal", *in.normal, in.colour);
  if (in.normal && !in.albedo)
    throw Error(path + ": a normal guide (" + in.normal_layer +
                ") without an albedo: the denoiser takes a normal only with an albedo (give --albedo)");
  for (const ImageF* image : {&in.colour, in.albedo ? &*in.albedo : nullptr, in.normal ? &*in.normal : nullptr})
    if (image)
      for (float v : image->rgb)
        if (!std::isfinite(v)) throw Error(path + ": holds NaN or infinite values (the denoiser takes finite ones)");
  return in;
}

}  // namespace caustica
