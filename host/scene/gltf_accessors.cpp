// Accessor reads for the glTF importer: every accessor is checked against its
// buffer view, and the view against its buffer, before a byte is read, in
// 64-bit arithmetic that cannot wrap; element strides and offsets follow the
// spec (byteStride 0 = tightly packed). Integer components convert as the
// spec's "normalized" flag says; non-finite floats are refused here, so no
// NaN or Inf position reaches the scene.
#include <cmath>
#include <cstring>

#include "host/limits.h"
#include "host/scene/gltf_internal.h"

namespace caustica::gltf_detail {

namespace {

struct View {
  const unsigned char* base = nullptr;  // nullptr: no bufferView, every value 0 (the spec's default)
  size_t count = 0, stride = 0, components = 0, component_size = 0;
  int component_type = 0;
  bool normalized = false;
  std::string pointer;  // "/accessors/<i>"
};

const char* component_name(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "byte";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "unsigned byte";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "short";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "unsigned short";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "unsigned int";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "float";
    default: return "an unknown component type";
  }
}

View checked_view(const Context& ctx, int index, const std::string& used_at) {
  const tinygltf::Model& m = ctx.model;
  const size_t i = checked_index(ctx, index, m.accessors.size(), used_at, "accessors");
  const tinygltf::Accessor& a = m.accessors[i];
  View v;
  v.pointer = "/accessors/" + std::to_string(i);
  if (a.sparse.isSparse) ctx.fail(v.pointer + "/sparse", "sparse accessors are not supported");
  v.component_type = a.componentType;
  const int size = a.componentType == TINYGLTF_COMPONENT_TYPE_INT || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE
                       ? -1  // not glTF 2.0 component types
                       : tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (size <= 0)
    ctx.fail(v.pointer + "/componentType", "expected 5120, 5121, 5122, 5123, 5125 or 5126, got " +
                                               std::to_string(a.componentType));
  const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (components <= 0) ctx.fail(v.pointer + "/type", "expected SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4");
  v.component_size = static_cast<size_t>(size);
  v.components = static_cast<size_t>(components);
  v.count = a.count;
  if (a.bufferView < 0 && v.count > limits::kMaxGltfZeroAccessorElements)
    ctx.fail(v.pointer + "/count", "expected at most " + std::to_string(limits::kMaxGltfZeroAccessorElements) +
                                       " elements in an accessor without a bufferView (the limit), got " +
                                       std::to_string(v.count));
  v.normalized = a.normalized;
  const uint64_t element = uint64_t(size) * uint64_t(components);
  v.stride = element;
  if (a.bufferView < 0) return v;  // all zeros
  const size_t vi = checked_index(ctx, a.bufferView, m.bufferViews.size(), v.pointer + "/bufferView", "bufferViews");
  const tinygltf::BufferView& bv = m.bufferViews[vi];
  const std::string vp = "/bufferViews/" + std::to_string(vi);
  const size_t bi = checked_index(ctx, bv.buffer, m.buffers.size(), vp + "/buffer", "buffers");
  const uint64_t buffer_bytes = m.buffers[bi].data.size();
  if (bv.byteOffset > buffer_bytes || bv.byteLength > buffer_bytes - bv.byteOffset)
    ctx.fail(vp, "expected byteOffset + byteLength within /buffers/" + std::to_string(bi) + " (" +
                     std::to_string(buffer_bytes) + " bytes), got " + std::to_string(bv.byteOffset) + " + " +
                     std::to_string(bv.byteLength));
  if (bv.byteStride != 0) {
    if (bv.byteStride < element || bv.byteStride > 252)
      ctx.fail(vp + "/byteStride", "expected a stride from the element size (" + std::to_string(element) +
                                       " bytes for " + v.pointer + ") to 252, got " + std::to_string(bv.byteStride));
    v.stride = bv.byteStride;
  }
  // Last byte read: byteOffset + stride * (count - 1) + element <= byteLength.
  const uint64_t length = bv.byteLength;
  const bool fits = v.count == 0 ||
                    (a.byteOffset <= length && v.count - 1 <= (length - a.byteOffset) / v.stride &&
                     a.byteOffset + v.stride * (v.count - 1) + element <= length);
  if (!fits)
    ctx.fail(v.pointer, "expected " + std::to_string(v.count) + " elements of " + std::to_string(element) +
                            " bytes (stride " + std::to_string(v.stride) + ") from byteOffset " +
                            std::to_string(a.byteOffset) + " to fit in " + vp + " (" + std::to_string(length) +
                            " bytes)");
  v.base = m.buffers[bi].data.data() + bv.byteOffset + a.byteOffset;
  return v;
}

double component(const View& v, size_t element, size_t c) {
  if (!v.base) return 0.0;
  const unsigned char* p = v.base + element * v.stride + c * v.component_size;
  switch (v.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return v.normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double s = static_cast<int8_t>(p[0]);
      return v.normalized ? std::fmax(s / 127.0, -1.0) : s;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t u;
      std::memcpy(&u, p, 2);
      return v.normalized ? u / 65535.0 : u;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t s;
      std::memcpy(&s, p, 2);
      return v.normalized ? std::fmax(s / 32767.0, -1.0) : s;
    }
    default: {  // UNSIGNED_INT
      uint32_t u;
      std::memcpy(&u, p, 4);
      return u;
    }
  }
}

void require_type(const Context& ctx, const View& v, size_t components, const char* type, const std::string& used_at) {
  if (v.components != components)
    ctx.fail(v.pointer + "/type", std::string("expected ") + type + " for its use at " + used_at);
}

// Texture coordinates and colours: float, or normalized unsigned byte or
// short (the specification's choices for both).
void require_float_or_normalized(const Context& ctx, const View& v, const char* what, const std::string& used_at) {
  const bool normalized_int = v.normalized && (v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                               v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  if (v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_int)
    ctx.fail(v.pointer + "/componentType", std::string("expected float, or normalized unsigned byte or short, for ") +
                                               what + " (used at " + used_at + "), got " +
                                               (v.normalized ? "normalized " : "") + component_name(v.component_type));
}

}  // namespace

std::vector<glm::vec3> read_vec3_accessor(const Context& ctx, int accessor, const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  require_type(ctx, v, 3, "VEC3", used_at);
  std::vector<glm::vec3> out(v.count);
  for (size_t e = 0; e < v.count; ++e) {
    for (size_t c = 0; c < 3; ++c) out[e][c] = static_cast<float>(component(v, e, c));
    if (!std::isfinite(out[e].x) || !std::isfinite(out[e].y) || !std::isfinite(out[e].z))
      ctx.fail(v.pointer, "element " + std::to_string(e) + " is not finite (" + std::to_string(out[e].x) + ", " +
                              std::to_string(out[e].y) + ", " + std::to_string(out[e].z) + "), used at " + used_at);
  }
  return out;
}

std::vector<glm::vec2> read_texcoord_accessor(const Context& ctx, int accessor, const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  require_type(ctx, v, 2, "VEC2", used_at);
  require_float_or_normalized(ctx, v, "texture coordinates", used_at);
  std::vector<glm::vec2> out(v.count);
  // glTF's v runs down the image from its top; ours up from its bottom
  // (kernels/lib/texture.h).
  for (size_t e = 0; e < v.count; ++e)
    out[e] = glm::vec2(static_cast<float>(component(v, e, 0)), 1.0f - static_cast<float>(component(v, e, 1)));
  return out;
}

std::vector<glm::vec4> read_tangent_accessor(const Context& ctx, int accessor, const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  require_type(ctx, v, 4, "VEC4", used_at);
  if (v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
    ctx.fail(v.pointer + "/componentType", "expected float tangents (used at " + used_at + "), got " +
                                               component_name(v.component_type));
  std::vector<glm::vec4> out(v.count);
  for (size_t e = 0; e < v.count; ++e) {
    for (size_t c = 0; c < 4; ++c) out[e][int(c)] = static_cast<float>(component(v, e, c));
    if (!std::isfinite(out[e].x + out[e].y + out[e].z + out[e].w))
      ctx.fail(v.pointer, "element " + std::to_string(e) + " is not finite, used at " + used_at);
  }
  return out;
}

std::vector<glm::vec4> read_colour_accessor(const Context& ctx, int accessor, const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  if (v.components != 3 && v.components != 4)
    ctx.fail(v.pointer + "/type", "expected VEC3 or VEC4 for its use at " + used_at);
  require_float_or_normalized(ctx, v, "vertex colours", used_at);
  std::vector<glm::vec4> out(v.count, glm::vec4(1.0f));
  for (size_t e = 0; e < v.count; ++e)
    for (size_t c = 0; c < v.components; ++c) {
      const double value = component(v, e, c);
      // Linear colours in [0, 1] (the specification's range for COLOR_n).
      if (!(value >= 0.0 && value <= 1.0))
        ctx.fail(v.pointer, "element " + std::to_string(e) + " has component " + std::to_string(value) +
                                ", expected a colour in [0, 1], used at " + used_at);
      out[e][int(c)] = static_cast<float>(value);
    }
  return out;
}

std::vector<uint32_t> read_index_accessor(const Context& ctx, int accessor, size_t vertex_count,
                                          const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  require_type(ctx, v, 1, "SCALAR", used_at);
  if (v.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT || v.component_type == TINYGLTF_COMPONENT_TYPE_BYTE ||
      v.component_type == TINYGLTF_COMPONENT_TYPE_SHORT || v.normalized)
    ctx.fail(v.pointer + "/componentType", "expected unsigned byte, short or int indices (used at " + used_at +
                                               "), got " + (v.normalized ? "normalized " : "") +
                                               component_name(v.component_type));
  std::vector<uint32_t> out(v.count);
  for (size_t e = 0; e < v.count; ++e) {
    const double index = component(v, e, 0);
    if (!(index < static_cast<double>(vertex_count)))
      ctx.fail(v.pointer, "element " + std::to_string(e) + " is index " + std::to_string(uint64_t(index)) +
                              ", out of range: the primitive has " + std::to_string(vertex_count) +
                              " vertices (indices used at " + used_at + ")");
    out[e] = static_cast<uint32_t>(index);
  }
  return out;
}

std::vector<double> read_accessor_values(const Context& ctx, int accessor, const std::string& used_at) {
  const View v = checked_view(ctx, accessor, used_at);
  std::vector<double> out;
  out.reserve(v.count * v.components);
  for (size_t e = 0; e < v.count; ++e)
    for (size_t c = 0; c < v.components; ++c) out.push_back(component(v, e, c));
  return out;
}

}  // namespace caustica::gltf_detail
