// glTF textures and images: an image's bytes (embedded in a buffer view or a
// data URI, or an external file tinygltf read through our bounded callbacks)
// stay encoded until a material uses them, then decode through the same
// checked decoder as every texture (textures.cpp: sizes against host/limits.h
// before any pixel is allocated). Samplers other than repeat, and texture
// coordinate sets other than TEXCOORD_0, are named in warnings.
#include <cmath>

#include "host/scene/gltf_internal.h"

namespace caustica::gltf_detail {

namespace {

// The image of /textures/<t>, decoded; "" or why not.
std::string decode(Context& ctx, size_t t, const std::string& pointer, LinearImage& out, size_t* image_index) {
  const tinygltf::Texture& tex = ctx.model.textures[t];
  const std::string tp = "/textures/" + std::to_string(t);
  if (tex.source < 0) return "it has no image source";
  const size_t i = checked_index(ctx, tex.source, ctx.model.images.size(), tp + "/source", "images");
  *image_index = i;
  const tinygltf::Image& image = ctx.model.images[i];
  const std::string ip = "/images/" + std::to_string(i);
  std::string bytes;
  if (image.bufferView >= 0) {
    const tinygltf::Model& m = ctx.model;
    const size_t vi = checked_index(ctx, image.bufferView, m.bufferViews.size(), ip + "/bufferView", "bufferViews");
    const tinygltf::BufferView& view = m.bufferViews[vi];
    const size_t bi = checked_index(ctx, view.buffer, m.buffers.size(), "/bufferViews/" + std::to_string(vi) + "/buffer",
                                    "buffers");
    const std::vector<unsigned char>& data = m.buffers[bi].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      ctx.fail("/bufferViews/" + std::to_string(vi),
               "expected byteOffset + byteLength within /buffers/" + std::to_string(bi) + " (" +
                   std::to_string(data.size()) + " bytes), got " + std::to_string(view.byteOffset) + " + " +
                   std::to_string(view.byteLength) + " (the image " + ip + ")");
    bytes.assign(reinterpret_cast<const char*>(data.data()) + view.byteOffset, view.byteLength);
  } else {
    bytes.assign(image.image.begin(), image.image.end());
  }
  if (bytes.empty())
    return ip + (image.uri.empty() ? std::string() : " (\"" + image.uri.substr(0, 200) + "\")") + " has no data";
  (void)pointer;
  const std::string why = decode_texture_image(bytes, out);
  return why.empty() ? why : ip + ": " + why;
}

double srgb_encode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

}  // namespace

int image_texture(Context& ctx, const tinygltf::TextureInfo& info, const std::string& pointer, bool linear_data) {
  const size_t t = checked_index(ctx, info.index, ctx.model.textures.size(), pointer + "/index", "textures");
  if (info.texCoord != 0)
    ctx.warn_once("texCoord", pointer + "/texCoord", "texture coordinate sets other than TEXCOORD_0 are not "
                                                     "supported; TEXCOORD_0 is used");
  if (info.extensions.count("KHR_texture_transform"))
    ctx.warn_once("texture transform", pointer + "/extensions/KHR_texture_transform",
                  "KHR_texture_transform is not supported; the texture is applied untransformed");
  const tinygltf::Texture& tex = ctx.model.textures[t];
  if (tex.sampler >= 0) {
    const size_t s = checked_index(ctx, tex.sampler, ctx.model.samplers.size(),
                                   "/textures/" + std::to_string(t) + "/sampler", "samplers");
    const tinygltf::Sampler& sampler = ctx.model.samplers[s];
    if (sampler.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT || sampler.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT)
      ctx.warn_once("wrap", "/samplers/" + std::to_string(s),
                    "clamped and mirrored texture wrapping are not supported; textures repeat");
  }
  // Decoded once per texture and use (colour or data) however many
  // materials use it.
  const std::pair<size_t, bool> key(t, linear_data);
  if (auto it = ctx.texture_indices.find(key); it != ctx.texture_indices.end()) return it->second;
  LinearImage img;
  size_t image_index = 0;
  std::string why = decode(ctx, t, pointer, img, &image_index);
  int index = -1;
  if (why.empty()) {
    // The decoder turned 8-bit codes into linear light; data textures mean
    // the codes themselves.
    if (linear_data)
      for (float& v : img.rgb) v = static_cast<float>(srgb_encode(v));
    why = ctx.textures.add_image(ctx.file + "#image" + std::to_string(image_index) + (linear_data ? "#linear" : ""),
                                 img, &index);
  }
  if (why.empty()) return ctx.texture_indices[key] = index;
  if (linear_data) {
    ctx.warn(pointer,
             "texture /textures/" + std::to_string(t) + " cannot be read: " + why + "; its factors are used alone");
    return ctx.texture_indices[key] = -1;
  }
  ctx.warn(pointer, "texture /textures/" + std::to_string(t) + " cannot be read: " + why +
                        "; using a magenta/black checker");
  return ctx.texture_indices[key] = ctx.textures.fallback();
}

}  // namespace caustica::gltf_detail
