// Reading a glTF file: the bytes (bounded, host/limits.h), tinygltf's parse
// with our file callbacks (external buffers and images are size-checked
// before they are read) and an image callback that keeps images encoded
// until a material uses them, then the checks on required extensions and the
// conversion (gltf_materials.cpp, gltf_geometry.cpp).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"
#include "host/scene/gltf_internal.h"

namespace caustica {
namespace gltf_detail {

void Context::fail(const std::string& pointer, const std::string& message) const {
  throw Error(file + ": " + (pointer.empty() ? "/" : pointer) + ": " + message);
}

void Context::warn(const std::string& pointer, const std::string& message) {
  out.warnings.push_back(file + ": " + (pointer.empty() ? "/" : pointer) + ": warning: " + message);
}

void Context::warn_once(const std::string& group, const std::string& pointer, const std::string& message) {
  auto [it, inserted] = once_.emplace(group, Once{out.warnings.size(), 0});
  if (inserted)
    warn(pointer, message);
  else
    ++it->second.more;
}

void Context::finish_warnings() {
  for (const auto& [group, once] : once_)
    if (once.more > 0)
      out.warnings[once.warning] += " (and " + std::to_string(once.more) + " more like it)";
  once_.clear();
}

size_t checked_index(const Context& ctx, int index, size_t size, const std::string& pointer, const char* array) {
  if (index < 0 || static_cast<size_t>(index) >= size)
    ctx.fail(pointer, "expected an index into /" + std::string(array) + " (0 to " +
                          (size == 0 ? std::string("none: it is empty") : std::to_string(size - 1)) + "), got " +
                          std::to_string(index));
  return static_cast<size_t>(index);
}

}  // namespace gltf_detail

namespace {

using namespace gltf_detail;
namespace fs = std::filesystem;

struct FileAccess {
  bool allowed = true;
};

bool file_exists(const std::string& path, void* user) {
  std::error_code ec;
  return static_cast<FileAccess*>(user)->allowed && fs::is_regular_file(path, ec);
}

std::string expand_path(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  if (!static_cast<FileAccess*>(user)->allowed) {
    *err = "external file \"" + path + "\" not read (files are off)";
    return false;
  }
  try {
    const std::string data = read_input_file(path, "glTF resource", limits::kMaxMeshFileBytes);
    out->assign(data.begin(), data.end());
    return true;
  } catch (const Error& e) {
    *err = e.what();
    return false;
  }
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "writing is not supported";
  return false;
}

// Images stay encoded here: decode_texture_image (textures.cpp) checks their
// size against host/limits.h before decoding, and only used ones are decoded.
// An image in a buffer view is not copied at all: tinygltf 2.7 hands over the
// view's bytes without checking the view against its buffer (a read past its
// end, found by fuzz_gltf); gltf_textures.cpp reads them with the checks.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0) image->image.assign(bytes, bytes + std::max(size, 0));
  image->width = image->height = image->component = -1;
  return true;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

// Extensions we read (FORMAT.md), those that carry no rendering meaning for
// us, and those without which the geometry cannot be read at all.
const std::set<std::string> kSupported = {"KHR_lights_punctual",         "KHR_materials_emissive_strength",
                                          "KHR_materials_transmission",  "KHR_materials_ior",
                                          "KHR_materials_pbrSpecularGlossiness", "KHR_mesh_quantization",
                                          "FB_ngon_encoding",            "KHR_texture_transform",
                                          "KHR_materials_clearcoat",     "KHR_materials_volume",
                                          "KHR_materials_specular"};
// A .glb's JSON chunk (the first, after the 12-byte header), or "" when the
// container is malformed (tinygltf then says how).
std::string glb_json_chunk(const std::string& bytes) {
  if (bytes.size() < 20 || bytes.compare(16, 4, "JSON") != 0) return "";
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const uint64_t length = uint64_t(b[12]) | uint64_t(b[13]) << 8 | uint64_t(b[14]) << 16 | uint64_t(b[15]) << 24;
  return length <= bytes.size() - 20 ? bytes.substr(20, length) : std::string();
}

// The 12-byte .glb header (issue 38: version 3 and a length one byte off
// were accepted): magic, version 2, and the file's length.
void check_glb_header(const std::string& path, const std::string& bytes) {
  if (bytes.size() < 12) throw Error(path + ": a binary glTF (.glb) of " + std::to_string(bytes.size()) + " bytes, shorter than its 12-byte header");
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  auto u32 = [&](size_t at) {
    return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
  };
  if (u32(4) != 2) throw Error(path + ": a binary glTF (.glb) header of version " + std::to_string(u32(4)) + " (expected 2: glTF 2.0)");
  if (u32(8) != bytes.size())
    throw Error(path + ": the binary glTF (.glb) header gives a length of " + std::to_string(u32(8)) + " bytes, the file has " +
                std::to_string(bytes.size()));
}

void check_extensions(Context& ctx) {
  const tinygltf::Model& m = ctx.model;
  for (size_t i = 0; i < m.extensionsRequired.size(); ++i) {
    const std::string& ext = m.extensionsRequired[i];
    const std::string pointer = "/extensionsRequired/" + std::to_string(i);
    if (extension_needed_for_geometry(ext))
      ctx.fail(pointer, "required extension " + ext + " is not supported (its geometry cannot be read without it; "
                        "decompress the file first, e.g. with gltf-transform)");
    if (!kSupported.count(ext))
      ctx.warn(pointer, "required extension " + ext + " is not supported; rendering the file without it");
  }
  for (size_t i = 0; i < m.extensionsUsed.size(); ++i) {
    const std::string& ext = m.extensionsUsed[i];
    const bool required =
        std::find(m.extensionsRequired.begin(), m.extensionsRequired.end(), ext) != m.extensionsRequired.end();
    if (!kSupported.count(ext) && !required)
      ctx.warn("/extensionsUsed/" + std::to_string(i), "extension " + ext + " is not supported; ignored");
  }
}

void compute_bounds(GltfModel& out) {
  if (out.mesh.triangles.empty()) return;
  out.lo = out.hi = out.mesh.triangles[0].p[0];
  for (const MeshTriangle& t : out.mesh.triangles)
    for (const glm::vec3& p : t.p) out.lo = glm::min(out.lo, p), out.hi = glm::max(out.hi, p);
}

}  // namespace

bool is_gltf_file(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".gltf" || ext == ".glb";
}

GltfModel import_gltf_bytes(const std::string& path, const std::string& bytes, const std::string& base_dir,
                            TextureLibrary& textures, bool allow_files, const glm::dmat4& root) {
  FileAccess access{allow_files};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(tinygltf::FsCallbacks{file_exists, expand_path, read_whole_file, refuse_write, &access});
  loader.SetImageLoader(keep_encoded_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
  if (bytes.size() > limits::kMaxMeshFileBytes)
    throw Error(path + ": file larger than the limit of " + format_bytes(limits::kMaxMeshFileBytes));
  if (binary) check_glb_header(path, bytes);
  check_schema(path, binary ? glb_json_chunk(bytes) : bytes, base_dir, allow_files);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, size, base_dir)
                         : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base_dir);
  if (!ok || !err.empty()) {
    std::string message;
    for (const std::string& line : lines_of(err)) message += (message.empty() ? "" : "; ") + line;
    throw Error(path + ": not a valid glTF 2.0 " + (binary ? "binary (.glb)" : "file") + ": " +
                (message.empty() ? std::string("tinygltf gives no reason") : message));
  }
  GltfModel out;
  for (const std::string& line : lines_of(warn)) out.warnings.push_back(path + ": warning: " + line);
  Context ctx(path, model, out, textures);
  check_extensions(ctx);
  convert_materials(ctx);
  convert_nodes(ctx, root);
  ctx.finish_warnings();
  out.camera_count = model.cameras.size();
  compute_bounds(out);
  return out;
}

GltfModel import_gltf(const std::string& path, TextureLibrary& textures, const glm::dmat4& root) {
  const std::string bytes = read_input_file(path, "glTF file", limits::kMaxMeshFileBytes);
  const fs::path dir = fs::path(path).parent_path();
  return import_gltf_bytes(path, bytes, dir.empty() ? std::string(".") : dir.string(), textures, true, root);
}

}  // namespace caustica
