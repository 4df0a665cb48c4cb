// Internal to the scene loader (load_scene.cpp, scene_materials.cpp,
// scene_shapes.cpp, scene_assets.cpp): the checked JSON readers every part
// uses, so that all messages share one format, and the state one load builds
// up (material and texture tables, per-triangle shading, mesh cache).
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "host/scene/load_scene.h"
#include "host/scene/mesh.h"
#include "host/scene/textures.h"

namespace caustica {
struct GltfModel;  // host/scene/gltf.h
}

namespace caustica::scene_detail {

// v / |v| at any magnitude a float holds (in double, where a float's square
// neither overflows nor underflows: [1e30, -1e30, 0] and [1e-30, 0, 0] are
// directions too); false for a zero or non-finite vector.
inline bool unit_direction(const glm::vec3& v, glm::vec3* unit) {
  const glm::dvec3 d(v);
  const double length = std::sqrt(glm::dot(d, d));
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  *unit = glm::vec3(d / length);
  return true;
}

using nlohmann::json;

// Reflectance: a colour or coefficient that scales reflected light, in
// [0, kMaxReflectance]. Coordinate: a position, |x| <= kMaxSceneCoordinate;
// Size: a length in (0, kMaxSceneCoordinate]; Extent: one in [0,
// kMaxSceneCoordinate] (host/limits.h).
enum class Range { Any, NonNegative, Positive, Reflectance, Coordinate, Size, Extent };

const char* range_words(Range r);
// The offending value as the user wrote it, shortened.
std::string describe(const json& v);
std::string lower(std::string s);
// A key as a JSON pointer token ("~" -> "~0", "/" -> "~1").
std::string pointer_token(const std::string& key);
// JSON text as a document, or caustica::Error naming `path`, the line and
// column and what was expected, in our words (numbers out of range with
// their JSON pointer, nesting deeper than limits::kMaxJsonDepth refused):
// the coursework loader's and the glTF importer's one parser.
json parse_json_text(const std::string& text, const std::string& path);

using KeyList = std::vector<const char*>;

// Holds what every message needs (the file name) and where warnings go; the
// readers below are the only places that check a value's type or range.
class Reader {
 public:
  Reader(std::string file, const LoadOptions& options) : file_(std::move(file)), options_(options) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message) const;
  [[noreturn]] void expected(const std::string& path, const std::string& what, const json& got) const;
  void warn(const std::string& path, const std::string& message) const;
  // A line that already names its file (from the texture or mesh modules).
  void forward_warning(const std::string& line) const;
  // Warnings that repeat per object (an unknown key on each of 400 spheres)
  // are reported once, at the end, with the first place and a count.
  void warn_once(const std::string& group, const std::string& path, const std::string& message) const;
  void flush_deferred() const;

  // Every key of `obj` must be in `known` or `also` (or start with "_": the
  // corpus writes comments as "_comment" keys). Unknown keys warn, or fail
  // under LoadOptions::strict.
  void check_keys(const json& obj, const std::string& path, const KeyList& known, const KeyList& also = {}) const;

  // nullptr when `key` is absent; `obj` is known to be an object.
  static const json* find(const json& obj, const char* key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }
  // The first of `keys` present (its name in *which), or nullptr.
  static const json* find_any(const json& obj, const KeyList& keys, const char** which = nullptr);
  const json& require(const json& obj, const char* key, const std::string& path, const std::string& what) const;

  const json& object(const json& v, const std::string& path) const;
  const json& array(const json& v, const std::string& path) const;
  std::string string(const json& v, const std::string& path) const;
  bool boolean(const json& v, const std::string& path) const;
  // Finite also in single precision: everything ends up in a float.
  float number(const json& v, const std::string& path, Range range) const;
  int integer(const json& v, const std::string& path, int lo, int hi) const;
  glm::vec3 vec3(const json& v, const std::string& path, Range range) const;
  glm::vec2 vec2(const json& v, const std::string& path, Range range) const;

  // Keyed forms: `fallback` makes the key optional.
  float read_number(const json& obj, const char* key, const std::string& path, Range range,
                    std::optional<float> fallback = std::nullopt) const;
  int read_int(const json& obj, const char* key, const std::string& path, int lo, int hi,
               std::optional<int> fallback = std::nullopt) const;
  glm::vec3 read_vec3(const json& obj, const char* key, const std::string& path, Range range,
                      std::optional<glm::vec3> fallback = std::nullopt) const;
  bool read_bool(const json& obj, const char* key, const std::string& path, bool fallback) const;
  std::string read_string(const json& obj, const char* key, const std::string& path,
                          std::optional<std::string> fallback = std::nullopt) const;
  const json& read_object(const json& obj, const char* key, const std::string& path) const;

  const LoadOptions& options() const { return options_; }
  const std::string& file() const { return file_; }

 private:
  struct Deferred {
    std::string path, message;
    size_t more = 0;
  };
  std::string file_;
  const LoadOptions& options_;
  mutable std::vector<Deferred> deferred_;
  mutable std::unordered_map<std::string, size_t> deferred_index_;
};

// Materials are stored once: generated scenes repeat a few materials over
// thousands of shapes. Keyed on the bytes (texture index included), which are
// fully defined because every field, padding included, is written.
class MaterialTable {
 public:
  explicit MaterialTable(std::vector<Material>& out) : out_(out) {}
  cs_uint add(const Material& m);

 private:
  std::vector<Material>& out_;
  std::unordered_map<std::string, cs_uint> index_;
};

// Finds the files a scene refers to. Student scenes name assets by absolute
// paths from their own machines or relative to a working directory that is
// not the scene's folder, so after the path as written (relative to the
// scene's folder) this tries the file name beside the scene, in models/ and
// textures/ there, and finally anywhere in the scene folder's tree (bounded
// search; the best match shares the most trailing path components with what
// was written).
class AssetFinder {
 public:
  AssetFinder(std::string scene_dir, std::string scene_stem)
      : dir_(std::move(scene_dir)), stem_(std::move(scene_stem)) {}
  // "" when nothing matches; `tried` (optional) receives a description of
  // where it looked, for the error message.
  std::string find(const std::string& written, const char* subfolder, std::string* tried = nullptr);

 private:
  void index_tree();
  std::string dir_, stem_;
  bool indexed_ = false;
  std::multimap<std::string, std::string> by_name_;  // lower-case file name -> path
};

struct LoadContext {
  LoadContext(const Reader& reader, Scene& s, std::string base_dir, std::string scene_stem)
      : r(reader), scene(s), dir(base_dir), materials(s.materials), textures(s),
        assets(std::move(base_dir), std::move(scene_stem)) {}

  const Reader& r;
  Scene& scene;
  std::string dir;  // the scene file's folder
  MaterialTable materials;
  TextureLibrary textures;
  AssetFinder assets;
  // One entry per scene triangle; kept only if some triangle has real data.
  std::vector<TriangleShading> shading;
  bool any_shading = false;
  // The same for tangents and vertex colours (glTF meshes).
  std::vector<TriangleTangents> tangents;
  std::vector<TriangleColours> colours;
  bool any_tangents = false, any_colours = false;
  std::map<std::string, std::shared_ptr<const Mesh>> meshes;  // by resolved path
  // glTF files placed as meshes: the Mesh above aliases the model's.
  std::map<std::string, std::shared_ptr<const GltfModel>> gltf_models;
  // Per load, so that a texture named by many shapes (found or missing) is
  // looked up, and warned about, once.
  std::map<std::string, int> image_textures;  // folder + "\n" + path as written -> index
  std::map<std::vector<float>, int> checker_textures;
};

// scene_materials.cpp
// The shape's "material" (defaults where absent), with textures from the
// material or from the shape itself. `key` names the material object
// ("material", "topmaterial", ...).
Material read_shape_material(LoadContext& ctx, const json& shape, const std::string& shape_path,
                             const char* key = "material");
// An OBJ/MTL material; textures resolve against the mesh's folder.
Material mesh_material(LoadContext& ctx, const MeshMaterial& m, const std::string& mesh_dir,
                       const std::string& path);
Material default_material();
// A "texture" value: a file name, or a procedural checkerboard object.
int read_texture(LoadContext& ctx, const json& v, const std::string& path);
// Index of the image texture `written` (a path in the scene or an MTL file,
// relative to `folder`); the fallback checker, with a warning, when missing.
int image_texture(LoadContext& ctx, const std::string& written, const std::string& folder, const std::string& path);

// scene_shapes.cpp
void read_shapes(LoadContext& ctx, const json& scene_obj);
// Appends one triangle with its shading record (`uv` null: the default UVs;
// `normals` null: the geometric normal) to ctx.scene, and its tangents
// (null: zero) and vertex colours (null: white).
void append_triangle(LoadContext& ctx, const glm::vec3 p[3], cs_uint material, const glm::vec2* uv,
                     const glm::vec3* normals = nullptr, const glm::vec4* tangents = nullptr,
                     const glm::vec4* colours = nullptr);
// Moves the shading records (tangents, colours) into the scene when any
// triangle has real ones.
void finish_shading(LoadContext& ctx);
// Degrees about x, then y, then z, about the world origin (right-handed):
// R = Rz * Ry * Rx (meshes' "rotate", the environment's "rotate").
glm::mat3 rotation_xyz(const glm::vec3& degrees);

}  // namespace caustica::scene_detail
