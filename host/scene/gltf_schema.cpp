// The glTF document's JSON checked against the types the schema gives its
// properties, before tinygltf reads it: tinygltf 2.7 skips a property of
// the wrong type and carries on with its default (a "pbrMetallicRoughness"
// that is an array becomes white, an index of -1 becomes "no texture"), so
// without this a broken file would render as something else without a word.
// The check is by property name wherever it appears (outside "extras", which
// is the author's own), which is how glTF names its properties: every name
// below has one type throughout the schema. Also here: required extensions
// without which the geometry cannot be read at all, reported before tinygltf
// trips over the missing buffer views.
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "host/error.h"
#include "host/limits.h"
#include "host/scene/gltf_internal.h"
#include "host/scene/scene_reader.h"

namespace caustica::gltf_detail {

namespace {

using nlohmann::json;

const std::set<std::string> kIndices = {"index",   "source", "sampler", "bufferView", "buffer", "mesh",
                                        "camera",  "material", "indices", "skin",     "scene",  "texCoord",
                                        "byteOffset", "byteLength", "byteStride", "count", "componentType",
                                        "mode",    "input",  "output",  "node",       "light",  "magFilter",
                                        "minFilter", "wrapS", "wrapT", "inverseBindMatrices", "skeleton"};
const std::set<std::string> kIndexLists = {"children", "nodes", "joints"};
const std::set<std::string> kStrings = {"name", "uri", "mimeType", "alphaMode", "version", "generator",
                                        "minVersion", "copyright", "interpolation", "path"};
const std::set<std::string> kObjects = {"pbrMetallicRoughness", "normalTexture", "occlusionTexture",
                                        "emissiveTexture", "baseColorTexture", "metallicRoughnessTexture",
                                        "attributes", "extensions", "asset", "perspective", "orthographic",
                                        "sparse", "values"};
const std::set<std::string> kArrays = {"primitives", "scenes", "meshes", "materials", "accessors",
                                       "bufferViews", "buffers", "images", "textures", "samplers",
                                       "cameras", "skins", "animations", "extensionsUsed",
                                       "extensionsRequired", "baseColorFactor", "emissiveFactor",
                                       "translation", "matrix", "min", "max", "targets",
                                       "weights", "channels", "lights"};
const std::set<std::string> kNumbers = {"metallicFactor", "roughnessFactor", "yfov", "znear", "zfar",
                                        "aspectRatio", "alphaCutoff", "strength", "intensity", "range",
                                        "xmag", "ymag", "innerConeAngle", "outerConeAngle",
                                        "emissiveStrength", "transmissionFactor", "ior"};

const std::set<std::string> kTopLevel = {"asset",     "scene",   "scenes",   "nodes",     "meshes",
                                         "materials", "accessors", "bufferViews", "buffers", "images",
                                         "textures",  "samplers", "cameras",  "skins",     "animations",
                                         "extensions", "extensionsUsed", "extensionsRequired"};
const std::set<std::string> kCheckedExtensions = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                                  "KHR_materials_transmission", "KHR_materials_ior",
                                                  "KHR_texture_transform"};

// An index or count as tinygltf keeps it: an int, so 2^32 + 1 must not
// wrap to 1 (issue 38) but be refused here.
bool non_negative_integer(const json& v) {
  if (v.is_number_unsigned()) return v.get<uint64_t>() <= uint64_t(std::numeric_limits<int>::max());
  return v.is_number_integer() && v.get<int64_t>() >= 0 && v.get<int64_t>() <= std::numeric_limits<int>::max();
}

// Sizes, which tinygltf keeps as size_t (their limits are checked where
// they are read, host/scene/gltf_accessors.cpp): any integer >= 0.
const std::set<std::string> kSizes = {"byteOffset", "byteLength", "byteStride", "count"};
bool non_negative_size(const json& v) {
  return v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0);
}

// Arrays whose elements are numbers: a string such as "NaN" there made the
// file invalid but loaded as the default value (issue 38).
const std::set<std::string> kNumberArrays = {"baseColorFactor", "emissiveFactor", "translation", "matrix",
                                             "min", "max", "weights", "color"};

class SchemaCheck {
 public:
  explicit SchemaCheck(const std::string& file) : file_(file) {}

  // `typed`: inside glTF's own properties, whose types are checked; the
  // author's "extras", unknown top-level properties and extensions we do
  // not read are only checked for depth (tinygltf converts extras and
  // extensions recursively).
  void value(const json& v, const std::string& pointer, int depth, bool typed = true) {
    if (depth > limits::kMaxJsonDepth)
      fail(pointer, "expected JSON nested at most " + std::to_string(limits::kMaxJsonDepth) + " levels deep");
    if (v.is_array()) {
      for (size_t i = 0; i < v.size(); ++i) value(v[i], pointer + "/" + std::to_string(i), depth + 1, typed);
    } else if (v.is_object()) {
      for (auto it = v.begin(); it != v.end(); ++it) {
        const std::string& key = it.key();
        const std::string p = pointer + "/" + scene_detail::pointer_token(key);
        bool typed_here = typed && key != "extras";
        // Properties glTF 2.0 does not define (glTF 1.0 leftovers such as
        // "techniques", vendor extensions) have schemas of their own.
        if (typed_here && pointer.empty() && !kTopLevel.count(key)) typed_here = false;
        if (typed_here && ends_with(pointer, "/extensions") && !kCheckedExtensions.count(key)) {
          if (!it->is_object()) expected(p, "an extension object", *it);
          typed_here = false;
        }
        if (typed_here) property(key, *it, p, pointer);
        value(*it, p, depth + 1, typed_here);
      }
    }
  }

 private:
  void property(const std::string& key, const json& v, const std::string& p, const std::string& parent) {
    // "attributes" maps names to accessor indices; an "extensions" object
    // maps extension names to objects.
    const bool in_primitive = parent.find("/primitives/") != std::string::npos;
    if (in_primitive && (ends_with(parent, "/attributes") || ends_with(parent, "/targets/" + last_token(parent)))) {
      if (!non_negative_integer(v)) expected(p, "an accessor index (an integer from 0 to 2147483647)", v);
      return;
    }
    if (ends_with(parent, "/extensions")) {
      if (!v.is_object()) expected(p, "an extension object", v);
      return;
    }
    if (key == "scenes" && parent.empty() && v.is_array() && v.empty())
      expected(p, "at least one scene (glTF: minItems 1)", v);
    if (kSizes.count(key)) {
      if (!non_negative_size(v)) expected(p, "a size (an integer >= 0)", v);
    } else if (kIndices.count(key) && !non_negative_integer(v)) {
      expected(p, "an index (an integer from 0 to 2147483647)", v);
    }
    const bool numbers_here = kNumberArrays.count(key) || ((key == "scale" || key == "rotation") && v.is_array());
    if (numbers_here && v.is_array())
      for (size_t i = 0; i < v.size(); ++i)
        if (!v[i].is_number()) expected(p + "/" + std::to_string(i), "a number", v[i]);
    if (kStrings.count(key) && !v.is_string()) expected(p, "a string", v);
    if (kObjects.count(key) && !v.is_object()) expected(p, "an object", v);
    if (kArrays.count(key) && !v.is_array()) expected(p, "an array", v);
    if (kNumbers.count(key) && !v.is_number()) expected(p, "a number", v);
    // A node's scale and rotation are arrays; KHR_texture_transform's a
    // number (rotation) and an array (scale), normalTexture's scale a number.
    if ((key == "scale" || key == "rotation") && !v.is_number() && !v.is_array())
      expected(p, "a number or an array of numbers", v);
    if (kIndexLists.count(key) && !(key == "nodes" && parent.empty())) {  // the top-level "nodes" holds objects
      if (!v.is_array()) expected(p, "an array of indices", v);
      for (size_t i = 0; i < v.size(); ++i)
        if (!non_negative_integer(v[i]))
          expected(p + "/" + std::to_string(i), "an index (an integer from 0 to 2147483647)", v[i]);
    }
  }

  static bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
  }
  static std::string last_token(const std::string& p) { return p.substr(p.find_last_of('/') + 1); }

  [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
    throw Error(file_ + ": " + (pointer.empty() ? "/" : pointer) + ": " + message);
  }
  [[noreturn]] void expected(const std::string& pointer, const std::string& what, const json& got) const {
    fail(pointer, "expected " + what + ", got " + scene_detail::describe(got));
  }

  const std::string& file_;
};

bool geometry_needs(const std::string& ext) {
  return ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" || ext == "KHR_meshopt_compression";
}

}  // namespace

bool extension_needed_for_geometry(const std::string& ext) { return geometry_needs(ext); }

namespace {

std::string percent_decode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) &&
        std::isxdigit((unsigned char)uri[i + 2])) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// A missing external buffer, named by its pointer (tinygltf says only
// "File not found").
void check_buffer_files(const std::string& file, const json& doc, const std::string& base_dir) {
  auto buffers = doc.find("buffers");
  if (buffers == doc.end()) return;
  for (size_t i = 0; i < buffers->size(); ++i) {
    const json& b = (*buffers)[i];
    auto uri = b.find("uri");
    if (uri == b.end() || uri->get_ref<const std::string&>().rfind("data:", 0) == 0) continue;
    const std::string written = uri->get<std::string>();
    const std::filesystem::path path = std::filesystem::path(base_dir) / percent_decode(written);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw Error(file + ": /buffers/" + std::to_string(i) + "/uri: expected an existing file, got \"" +
                  written.substr(0, 200) + "\" (not found at " + path.lexically_normal().string() + ")");
  }
}

}  // namespace

void check_schema(const std::string& file, const std::string& json_text, const std::string& base_dir,
                  bool allow_files) {
  if (json_text.empty()) return;  // a .glb without a JSON chunk: tinygltf says how
  const json doc = scene_detail::parse_json_text(json_text, file);
  if (!doc.is_object()) throw Error(file + ": /: expected a glTF JSON object, got " + scene_detail::describe(doc));
  SchemaCheck(file).value(doc, "", 0);
  if (allow_files) check_buffer_files(file, doc, base_dir);
  if (auto it = doc.find("extensionsRequired"); it != doc.end())
    for (size_t i = 0; i < it->size(); ++i)
      if ((*it)[i].is_string() && geometry_needs((*it)[i].get<std::string>()))
        throw Error(file + ": /extensionsRequired/" + std::to_string(i) + ": required extension " +
                    (*it)[i].get<std::string>() +
                    " is not supported (the geometry cannot be read without it; decompress the file first, e.g. "
                    "with gltf-transform)");
}

}  // namespace caustica::gltf_detail
