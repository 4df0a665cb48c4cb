// Private to the glTF importer (gltf_*.cpp; public API in gltf.h): the state
// one import builds up and the checked readers of tinygltf's model, so that
// every message has one form, "<file>: <JSON pointer>: <what>", and every
// unsupported feature is warned about once per file.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <set>

#include "host/scene/gltf.h"

namespace caustica::gltf_detail {

// One mesh primitive as read from its accessors (gltf_primitives.cpp).
struct DecodedPrimitive {
  std::string pointer;  // "/meshes/<m>/primitives/<p>"
  int material = -1;
  std::vector<glm::vec3> p, n;  // n: empty or one per position
  std::vector<glm::vec2> uv;    // empty or one per position
  std::vector<glm::vec4> colours;  // COLOR_0: empty or one per position
  // Empty, or one per corner where the material has a normal map: the
  // TANGENT attribute's, or MikkTSpace's (host/scene/mesh_tangents.h).
  std::vector<glm::vec4> corner_tangents;
  std::vector<uint32_t> corners;  // three per triangle, into p
};

class Context {
 public:
  Context(std::string file, const tinygltf::Model& model, GltfModel& out, TextureLibrary& textures)
      : file(std::move(file)), model(model), out(out), textures(textures) {}

  [[noreturn]] void fail(const std::string& pointer, const std::string& message) const;
  void warn(const std::string& pointer, const std::string& message);
  // Once per `group` per file; later occurrences are counted in the message
  // written by finish_warnings().
  void warn_once(const std::string& group, const std::string& pointer, const std::string& message);
  void finish_warnings();

  const std::string file;
  const tinygltf::Model& model;
  GltfModel& out;
  TextureLibrary& textures;
  std::map<size_t, std::vector<DecodedPrimitive>> decoded_meshes;  // by mesh index
  // (/textures/<i>, stored as linear data) -> index in `textures`, once decoded
  std::map<std::pair<size_t, bool>, int> texture_indices;
  // Texture coordinate sets: those each material's textures name (its
  // textureInfos' texCoord, or their KHR_texture_transform's), gathered
  // while the material is mapped (`mapping_material`), and the one set its
  // primitives read as their texture coordinates (convert_materials).
  int mapping_material = -1;
  std::vector<std::set<int>> uv_sets_named;
  std::vector<int> material_uv_set;

 private:
  struct Once {
    size_t warning = 0;  // index into out.warnings
    size_t more = 0;
  };
  std::map<std::string, Once> once_;
};

// An index the file wrote, checked against the array it points into.
// `pointer` is where the index is written ("/meshes/0/primitives/1/indices").
size_t checked_index(const Context& ctx, int index, size_t size, const std::string& pointer, const char* array);

// --- gltf_schema.cpp ----------------------------------------------------
// Checks the document's JSON against the types glTF gives its properties,
// and its required extensions against those the geometry needs; throws
// caustica::Error naming the file and the pointer. Unparsable text passes
// (tinygltf reports the syntax error).
// With allow_files, external buffers must exist under base_dir.
void check_schema(const std::string& file, const std::string& json_text, const std::string& base_dir,
                  bool allow_files);
bool extension_needed_for_geometry(const std::string& ext);

// --- gltf_accessors.cpp -------------------------------------------------
// Accessor data as read: range-checked against its buffer view and buffer
// before a byte is touched. `used_at` is the pointer of the reference, for
// messages about what the use requires.
std::vector<glm::vec3> read_vec3_accessor(const Context& ctx, int accessor, const std::string& used_at);
// TEXCOORD_n: float, or normalized unsigned byte/short.
std::vector<glm::vec2> read_texcoord_accessor(const Context& ctx, int accessor, const std::string& used_at);
// TANGENT: float VEC4 (xyz direction, w the bitangent sign), finite.
std::vector<glm::vec4> read_tangent_accessor(const Context& ctx, int accessor, const std::string& used_at);
// COLOR_n: VEC3 or VEC4 (alpha 1 for VEC3), float or normalized unsigned
// byte/short, each component in [0, 1].
std::vector<glm::vec4> read_colour_accessor(const Context& ctx, int accessor, const std::string& used_at);
// Indices (unsigned byte, short or int scalars), each below vertex_count.
std::vector<uint32_t> read_index_accessor(const Context& ctx, int accessor, size_t vertex_count,
                                          const std::string& used_at);
// The elements of an accessor (for fuzzing and tests of stride/offset):
// count x components values converted to double.
std::vector<double> read_accessor_values(const Context& ctx, int accessor, const std::string& used_at);

// --- gltf_geometry.cpp --------------------------------------------------
// Walks the scene's node graph: triangles of every mesh instance, placed
// cameras and lights.
void convert_nodes(Context& ctx, const glm::dmat4& root);
// The local transform of /nodes/<i> (matrix, or T * R * S).
glm::dmat4 node_local_transform(const Context& ctx, size_t node);

// --- gltf_primitives.cpp ------------------------------------------------
// The triangles of every primitive of /meshes/<mesh> under `world`, into
// ctx.out.mesh.
void add_mesh_instance(Context& ctx, size_t mesh, const glm::dmat4& world);

// --- gltf_materials.cpp -------------------------------------------------
// One Material per /materials entry, in order, into ctx.out.materials.
void convert_materials(Context& ctx);

// --- gltf_textures.cpp --------------------------------------------------
// The texture /textures/<info.index> in ctx.textures (decoded once per
// image); the magenta/black fallback, with a warning, when its image is
// missing or unreadable. With linear_data (glTF's data textures:
// metallicRoughnessTexture) the texels hold the 8-bit codes / 255 as they
// are, not sRGB-decoded, and an unreadable image gives -1 (the factors
// alone, with a warning): a checker would be read as roughness.
// The textureInfo's KHR_texture_transform and its texture's sampler (wrap
// modes, magnification filter) give the record its sampling (lib/texture.h).
int image_texture(Context& ctx, const tinygltf::TextureInfo& info, const std::string& pointer,
                  bool linear_data = false);

}  // namespace caustica::gltf_detail
