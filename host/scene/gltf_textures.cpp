// glTF textures and images: an image's bytes (embedded in a buffer view or a
// data URI, or an external file tinygltf read through our bounded callbacks)
// stay encoded until a material uses them, then decode through the same
// checked decoder as every texture (textures.cpp: sizes against host/limits.h
// before any pixel is allocated). A sampler's wrap modes and magnification
// filter, and a use's KHR_texture_transform, become the Texture record's
// sampling (lib/texture.h), one record per distinct way an image is read.
// Texture coordinate sets other than TEXCOORD_0 are named in warnings.
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

// A sampler's wrap mode as Texture.sampling's bits for one axis.
cs_uint wrap_bits(const Context& ctx, int mode, cs_uint clamp_bit, cs_uint mirror_bit, const std::string& pointer) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return 0u;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return clamp_bit;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return mirror_bit;
    default:
      ctx.fail(pointer, "expected 10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648 (MIRRORED_REPEAT), got " +
                            std::to_string(mode));
  }
}

// `count` finite numbers of a KHR_texture_transform property.
std::vector<double> transform_numbers(const Context& ctx, const tinygltf::Value& ext, const char* key, size_t count,
                                      std::vector<double> fallback, const std::string& pointer) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  const std::string p = pointer + "/" + key;
  const std::string expected = count == 1 ? "a finite number" : "an array of " + std::to_string(count) + " finite numbers";
  if (count == 1) {
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) ctx.fail(p, "expected " + expected);
    return {v.GetNumberAsDouble()};
  }
  if (!v.IsArray() || v.ArrayLen() != count) ctx.fail(p, "expected " + expected);
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i) {
    const tinygltf::Value& e = v.Get(int(i));
    if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble())) ctx.fail(p + "/" + std::to_string(i), "expected a finite number");
    out.push_back(e.GetNumberAsDouble());
  }
  return out;
}

// KHR_texture_transform's map in this format's uv. The extension's is
// uv' = T(offset) R(rotation) S(scale) uv in glTF's uv, whose v runs down
// the image, with R = [cos sin; -sin cos]: what the extension's own test
// model (TextureTransformTest: the arrow must point at the green marker,
// not the red one) shows as correct; its README's GLSL, read column by
// column, turns the other way. Ours has v' = 1 - v on both sides, so with
// glTF's rows (a b c), (d e f): u' = a u - b v + (b + c),
// v' = -d u + e v + (1 - e - f).
void texture_transform(const Context& ctx, const tinygltf::Value& ext, const std::string& pointer, glm::vec3* uv_u,
                       glm::vec3* uv_v) {
  if (!ext.IsObject()) ctx.fail(pointer, "expected an object");
  const std::vector<double> offset = transform_numbers(ctx, ext, "offset", 2, {0.0, 0.0}, pointer);
  const double rotation = transform_numbers(ctx, ext, "rotation", 1, {0.0}, pointer)[0];
  const std::vector<double> scale = transform_numbers(ctx, ext, "scale", 2, {1.0, 1.0}, pointer);
  const double c = std::cos(rotation), s = std::sin(rotation);
  const double a = c * scale[0], b = s * scale[1], d = -s * scale[0], e = c * scale[1];
  *uv_u = glm::vec3(float(a), float(-b), float(b + offset[0]));
  *uv_v = glm::vec3(float(-d), float(e), float(1.0 - e - offset[1]));
}

double srgb_encode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// /textures/<t>'s image as decoded (repeat, bilinear, untransformed): the
// record image_texture reads another way where a sampler or transform asks.
int decoded_texture(Context& ctx, size_t t, const std::string& pointer, bool linear_data) {
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

}  // namespace

int image_texture(Context& ctx, const tinygltf::TextureInfo& info, const std::string& pointer, bool linear_data) {
  const size_t t = checked_index(ctx, info.index, ctx.model.textures.size(), pointer + "/index", "textures");
  int tex_coord = info.texCoord;
  cs_uint sampling = 0u;
  glm::vec3 uv_u(1.0f, 0.0f, 0.0f), uv_v(0.0f, 1.0f, 0.0f);
  if (auto it = info.extensions.find("KHR_texture_transform"); it != info.extensions.end()) {
    const std::string tp = pointer + "/extensions/KHR_texture_transform";
    texture_transform(ctx, it->second, tp, &uv_u, &uv_v);
    if (uv_u != glm::vec3(1.0f, 0.0f, 0.0f) || uv_v != glm::vec3(0.0f, 1.0f, 0.0f)) sampling |= TEXTURE_TRANSFORMED;
    if (it->second.Has("texCoord")) {
      const tinygltf::Value& v = it->second.Get("texCoord");
      if (!v.IsInt() || v.Get<int>() < 0) ctx.fail(tp + "/texCoord", "expected a non-negative integer");
      tex_coord = v.Get<int>();  // overrides the textureInfo's (the extension says)
    }
  }
  if (ctx.mapping_material >= 0) ctx.uv_sets_named[size_t(ctx.mapping_material)].insert(tex_coord);
  const tinygltf::Texture& tex = ctx.model.textures[t];
  if (tex.sampler >= 0) {
    const size_t s = checked_index(ctx, tex.sampler, ctx.model.samplers.size(),
                                   "/textures/" + std::to_string(t) + "/sampler", "samplers");
    const tinygltf::Sampler& sampler = ctx.model.samplers[s];
    const std::string sp = "/samplers/" + std::to_string(s);
    sampling |= wrap_bits(ctx, sampler.wrapS, TEXTURE_CLAMP_U, TEXTURE_MIRROR_U, sp + "/wrapS");
    sampling |= wrap_bits(ctx, sampler.wrapT, TEXTURE_CLAMP_V, TEXTURE_MIRROR_V, sp + "/wrapT");
    // Magnification decides: no mip-maps here, and a path tracer's texels
    // are mostly seen up close (FORMAT.md).
    if (sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) sampling |= TEXTURE_NEAREST;
  }
  return ctx.textures.sampled(decoded_texture(ctx, t, pointer, linear_data), sampling, uv_u, uv_v);
}

}  // namespace caustica::gltf_detail
