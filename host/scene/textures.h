// Scene textures: images (stb_image: PNG, JPG, PPM/PGM, BMP, TGA, HDR) and
// procedural checkerboards, packed into the Scene's one texel buffer of
// linear half floats with a Texture record each (kernels/shared/types.h);
// the fourth half of a texel is the image's alpha (1 where it has none),
// read only by alpha cut-outs (kernels/lib/alpha_cutout.h).
// 8-bit images are sRGB-encoded and decoded to linear here; HDR stays linear.
// A texture that cannot be found or read is not an error: it becomes a
// visible magenta/black checker and a warning naming it.
#pragma once

#include <glm/glm.hpp>

#include <map>
#include <string>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Where a texture path written in a scene may be: as written (absolute, or
// relative to the scene's folder), then by file name beside the scene, in
// <scene folder>/textures/, and in the repository's textures/ folder
// (students wrote absolute paths from their own machines). Returns "" when
// none exists.
std::string resolve_texture_path(const std::string& written, const std::string& scene_dir);

// The paths resolve_texture_path tries, in order (for messages and tests).
std::vector<std::string> texture_search_candidates(const std::string& written, const std::string& scene_dir);

// The exact sRGB EOTF of an 8-bit code value (what 8-bit texels decode to).
float srgb_byte_to_linear(unsigned char value);

// Row-major from the top row, 3 linear floats per texel; alpha (one per
// texel, linear) only for images that have it, empty otherwise.
struct LinearImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  std::vector<float> alpha;
};

// Decodes a texture file's bytes (any format listed above). Returns "" on
// success, else why not; sizes beyond host/limits.h's texture limits, and
// headers declaring more pixels than the bytes can hold, are refused before
// any pixel memory is allocated. The fuzz target fuzz/fuzz_texture.cpp calls
// it directly.
std::string decode_texture_image(const std::string& data, LinearImage& out);

// The mean of the scene's texture `index` over its image (linear rgb as
// stored; a checker's two colours averaged): the integral over a whole
// tile of what the kernels' lookup returns (lib/texture.h: bilinear with
// wrap keeps the mean). An emission texture's light is picked by it
// (host/lights/light_table.cpp).
glm::vec3 mean_texel(const Scene& scene, int index);

class TextureLibrary {
 public:
  explicit TextureLibrary(Scene& scene) : scene_(scene) {}

  // Index of the texture for `written` (loaded once per resolved file). On a
  // missing or unreadable file: appends a warning naming `context` and the
  // path, and returns the magenta/black fallback checker.
  int image(const std::string& written, const std::string& scene_dir, const std::string& context,
            std::vector<std::string>& warnings);
  int checker(const glm::vec3& color1, const glm::vec3& color2, float scale);
  // An image decoded elsewhere (a glTF file's embedded images), stored once
  // per `key`. Returns "" and its index in *index, or why it cannot be
  // stored (the texel buffer's 2^32 limit; an empty image).
  std::string add_image(const std::string& key, const LinearImage& image, int* index);
  // The visible stand-in for a texture that cannot be read: a magenta/black checker.
  int fallback();
  // Image texture `base` read another way (Texture.sampling bits, and with
  // TEXTURE_TRANSFORMED the affine uv map whose rows are uv_u, uv_v): a
  // record sharing its texels, once per distinct way. A checker is
  // returned as it is.
  int sampled(int base, cs_uint sampling, const glm::vec3& uv_u, const glm::vec3& uv_v);

 private:
  Scene& scene_;
  std::map<std::string, int> by_path_;
  std::map<std::string, std::string> failed_;  // resolved path -> why it could not be read
  int fallback_ = -1;
  std::map<std::vector<float>, int> sampled_;  // (base, sampling, uv_u, uv_v) -> index
};

}  // namespace caustica
