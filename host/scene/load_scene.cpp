#include "host/scene/load_scene.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "host/error.h"
#include "host/limits.h"
#include "host/lights/environment_light.h"
#include "host/lights/light_types.h"
#include "host/read_file.h"
#include "host/scene/gltf.h"
#include "host/scene/scene_reader.h"

namespace caustica {

namespace {

using namespace scene_detail;


const KeyList kTopKeys = {"nbounces", "rendermode", "camera", "scene", "aperture", "focus_distance", "use_dof"};
// Settings of the authors' own renderers (sampling, acceleration, post
// processing): they do not change what the scene is, so they pass silently.
const KeyList kTopIgnored = {"nsamples",
                             "shadow samples",
                             "camera samples",
                             "bvh",
                             "lens_sampling",
                             "use_denoiser",
                             "use_tone_mapping",
                             "use_stratified_sampling",
                             "use_bvh",
                             "use_gaussian_blur",
                             "use_importance_sampling",
                             "importance_sampling_min_samples",
                             "importance_sampling_max_samples",
                             "FramesNum",
                             "animation path"};
const KeyList kApertureKeys = {"aperture", "apertureSize", "diameter"};
const KeyList kFocusKeys = {"focalDistance", "focusDistance", "focusdistance", "focalLength", "focus_distance"};
const KeyList kCameraKeys = {"type",     "width",        "height",   "position",      "lookAt",
                             "upVector", "fov",          "exposure", "aperture",      "apertureSize",
                             "diameter", "focalDistance", "focusDistance", "focusdistance", "focalLength",
                             "focus_distance"};
// tone_mapping: the CLI chooses the tone curve; position0.. / movement0..:
// camera animation (a still of the first frame is rendered, with a warning).
const KeyList kCameraIgnored = {"tone_mapping", "position0", "position1", "position2", "movement0", "movement1"};

// The file's choice of integrator; every spelling the coursework variants
// use for path tracing reads as Path (the renderer says whether it is built).
RenderMode read_mode(const Reader& r, const json& top) {
  const json* v = Reader::find(top, "rendermode");
  if (!v) return RenderMode::Phong;
  const std::string name = lower(r.string(*v, "/rendermode"));
  if (name == "binary") return RenderMode::Binary;
  if (name == "phong") return RenderMode::Phong;
  if (name == "pathtracer" || name == "pathtracing" || name == "path") return RenderMode::Path;
  r.expected("/rendermode", "one of \"binary\", \"phong\", \"pathtracer\" (or \"pathtracing\", \"path\")", *v);
  return RenderMode::Phong;
}

CameraDesc read_camera(const Reader& r, const json& top, bool* animated) {
  const std::string path = "/camera";
  const json& cam = r.read_object(top, "camera", "");
  r.check_keys(cam, path, kCameraKeys, kCameraIgnored);
  const std::string type = r.read_string(cam, "type", path, std::string("pinhole"));
  const std::string t = lower(type);
  const bool lens_type = t == "finiteaperture" || t == "finite-aperture" || t == "thinlens" || t == "aperture";
  if (t != "pinhole" && !lens_type)
    r.warn(path + "/type", "camera type \"" + type + "\" is not supported; rendering it as a pinhole camera");
  CameraDesc c;
  c.width = r.read_int(cam, "width", path, 1, 32768);
  c.height = r.read_int(cam, "height", path, 1, 32768);
  // An animated camera (position0, position1, ... keyed by movement0, ...)
  // has no "position"; its first keyframe stands in.
  if (!Reader::find(cam, "position") && Reader::find(cam, "position0")) {
    c.position = r.read_vec3(cam, "position0", path, Range::Coordinate);
    *animated = true;
  } else {
    c.position = r.read_vec3(cam, "position", path, Range::Coordinate);
  }
  if (Reader::find(cam, "movement0") || Reader::find(cam, "position1")) *animated = true;
  c.look_at = r.read_vec3(cam, "lookAt", path, Range::Coordinate);
  c.up = r.read_vec3(cam, "upVector", path, Range::Any);
  const std::string fov_what = "a vertical field of view in degrees, 0 < fov < 180";
  const json& fov = r.require(cam, "fov", path + "/fov", fov_what);
  c.fov_y_degrees = r.number(fov, path + "/fov", Range::Any);
  if (!(c.fov_y_degrees > 0.0f && c.fov_y_degrees < 180.0f)) r.expected(path + "/fov", fov_what, fov);
  c.exposure = r.read_number(cam, "exposure", path, Range::Any, 0.0f);
  // 2^exposure scales every pixel: beyond the limit it is 0 or inf in float.
  if (std::fabs(c.exposure) > limits::kMaxExposureStops)
    r.expected(path + "/exposure",
               "an exposure in stops within [-" + std::to_string(int(limits::kMaxExposureStops)) + ", " +
                   std::to_string(int(limits::kMaxExposureStops)) + "] (the limit)",
               cam["exposure"]);
  try {
    camera_basis(c);
  } catch (const Error& e) {
    r.fail(path, e.what());
  }

  // Depth of field: on the camera under several names, or (one repository)
  // at the top level next to "use_dof". Every aperture spelling is read as
  // the lens diameter, the photographic meaning and that of the "Ray Tracing
  // in One Weekend" camera most students followed.
  const char* which = nullptr;
  std::string where = path;
  const json* aperture = Reader::find_any(cam, kApertureKeys, &which);
  if (!aperture && (aperture = Reader::find(top, "aperture"))) where = "", which = "aperture";
  if (aperture) c.aperture_radius = 0.5f * r.number(*aperture, where + "/" + which, Range::Extent);
  where = path;
  const json* focus = Reader::find_any(cam, kFocusKeys, &which);
  if (!focus && (focus = Reader::find(top, "focus_distance"))) where = "", which = "focus_distance";
  c.focus_distance = focus ? r.number(*focus, where + "/" + which, Range::Size)
                           : glm::length(glm::dvec3(c.look_at) - glm::dvec3(c.position));
  if (!r.read_bool(top, "use_dof", "", true)) c.aperture_radius = 0.0f;
  if (lens_type && !aperture)
    r.warn(path + "/type", "camera type \"" + type + "\" without an aperture (\"aperture\", \"apertureSize\" or "
                           "\"diameter\"); it is a pinhole camera");
  return c;
}

void read_lights(const Reader& r, const json& scene_obj, Scene& out) {
  const json* list = Reader::find(scene_obj, "lightsources");
  if (!list) return;
  const std::string base = "/scene/lightsources";
  r.array(*list, base);
  const std::string what = "a light type: " + light_file_types() + " or \"ambient\"";
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string path = base + "/" + std::to_string(i);
    const json& l = r.object((*list)[i], path);
    const std::string type = lower(r.string(r.require(l, "type", path + "/type", what), path + "/type"));
    if (type == "ambient") {
      r.check_keys(l, path, {"type", "intensity"});
      out.ambient_light = out.ambient_light.value_or(glm::vec3(0.0f)) + r.read_vec3(l, "intensity", path, Range::NonNegative);
    } else if (const LightType* light = light_type_of_file(type)) {
      light->read(r, l, path, out);  // host/lights/<type>_light.cpp
      out.light_sources.resize(out.lights.size(), path);
    } else {
      r.expected(path + "/type", what, l["type"]);
    }
  }
}

std::pair<size_t, size_t> line_column(const std::string& text, size_t byte) {
  // nlohmann's byte is the 1-based index of the last character it read.
  const size_t pos = std::min(byte > 0 ? byte - 1 : 0, text.size());
  const size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + pos, '\n'));
  const size_t nl = pos == 0 ? std::string::npos : text.rfind('\n', pos - 1);
  return {line, nl == std::string::npos ? pos + 1 : pos - nl};
}

// nlohmann's what() starts "[json.exception.parse_error.101] parse error at
// line 2, column 8: "; keep only the explanation after it.
std::string parse_reason(const std::string& what) {
  const size_t col = what.find("column ");
  const size_t colon = what.find(": ", col == std::string::npos ? 0 : col);
  return colon == std::string::npos ? what : what.substr(colon + 2);
}

// Builds the DOM like json::parse but remembers the JSON path being read, so
// that a number nlohmann refuses (1e999 overflows: out_of_range 406, which
// carries no position) is reported like any other bad value. Nesting deeper
// than limits::kMaxJsonDepth stops the parse: the parser itself keeps its
// own stack, but every later walk of the document recurses per level.
class PathTrackingSax {
 public:
  explicit PathTrackingSax(json& out) : dom_(out, /*allow_exceptions=*/false) {}

  bool null() { return value(dom_.null()); }
  bool boolean(bool v) { return value(dom_.boolean(v)); }
  bool number_integer(json::number_integer_t v) { return value(dom_.number_integer(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return value(dom_.number_unsigned(v)); }
  bool number_float(json::number_float_t v, const std::string& s) { return value(dom_.number_float(v, s)); }
  bool string(std::string& v) { return value(dom_.string(v)); }
  bool binary(json::binary_t& v) { return value(dom_.binary(v)); }
  bool start_object(std::size_t n) {
    if (too_deep()) return false;
    frames_.push_back(Frame{false, 0, {}});
    return dom_.start_object(n);
  }
  bool key(std::string& k) {
    frames_.back().key = k;
    return dom_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return value(dom_.end_object());
  }
  bool start_array(std::size_t n) {
    if (too_deep()) return false;
    frames_.push_back(Frame{true, 0, {}});
    return dom_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return value(dom_.end_array());
  }
  bool parse_error(std::size_t byte, const std::string& token, const nlohmann::detail::exception& e) {
    error_byte = byte;
    error_token = token;
    error_id = e.id;
    error_what = e.what();
    error_path = path();
    return false;
  }

  bool nested_too_deep = false;
  size_t error_byte = 0;
  int error_id = 0;
  std::string error_token, error_what, error_path;

 private:
  struct Frame {
    bool array;
    size_t index;
    std::string key;
  };
  // The first levels of the path being read; deep paths end in "/...".
  std::string path(size_t max_levels = 1000) const {
    std::string p;
    for (size_t i = 0; i < frames_.size(); ++i) {
      if (i == max_levels) return p + "/...";
      const Frame& f = frames_[i];
      p += "/" + (f.array ? std::to_string(f.index) : pointer_token(f.key));
    }
    return p;
  }
  bool too_deep() {
    if (frames_.size() < static_cast<size_t>(limits::kMaxJsonDepth)) return false;
    nested_too_deep = true;
    error_path = path(6);
    return true;
  }
  // A complete value moves the enclosing array on to its next element.
  bool value(bool ok) {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return ok;
  }
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
};


}  // namespace

namespace scene_detail {
json parse_json_text(const std::string& text, const std::string& path) {
  json j;
  PathTrackingSax sax(j);
  if (json::sax_parse(text, &sax, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true)) return j;
  if (sax.nested_too_deep)
    throw Error(path + ": " + sax.error_path + ": expected JSON nested at most " +
                std::to_string(limits::kMaxJsonDepth) + " levels deep (the limit; a scene needs 5), got deeper");
  const auto [line, column] = line_column(text, sax.error_byte);
  const std::string where = path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
  if (sax.error_id == 406)
    throw Error(where + (sax.error_path.empty() ? "/" : sax.error_path) + ": expected a finite number, got " +
                sax.error_token + " (out of range)");
  throw Error(where + "JSON syntax error: " + parse_reason(sax.error_what));
}

}  // namespace scene_detail

Scene parse_scene(const json& j, const std::string& file_for_messages, const std::string& base_dir,
                  const LoadOptions& options) {
  const Reader r(file_for_messages, options);
  r.object(j, "");
  r.check_keys(j, "", kTopKeys, kTopIgnored);
  Scene scene;
  scene.source_path = file_for_messages;
  scene.nbounces = r.read_int(j, "nbounces", "", 0, 1024, 4);
  scene.mode = read_mode(r, j);
  bool animated = Reader::find(j, "FramesNum") || Reader::find(j, "animation path");
  scene.camera = read_camera(r, j, &animated);
  if (animated)
    r.warn("", "animation (FramesNum, \"animation path\", camera position0.., movement0..) is not supported; "
               "rendering a still from the first camera position");
  const json& sc = r.read_object(j, "scene", "");
  r.check_keys(sc, "/scene", {"backgroundcolor", "lightsources", "shapes", "ambientlight", "environment"});
  scene.background = r.read_vec3(sc, "backgroundcolor", "/scene", Range::NonNegative, glm::vec3(0.0f));
  if (sc.contains("ambientlight")) scene.ambient_light = r.read_vec3(sc, "ambientlight", "/scene", Range::NonNegative);
  read_lights(r, sc, scene);
  namespace fs = std::filesystem;
  LoadContext ctx(r, scene, base_dir.empty() ? std::string(".") : base_dir,
                  fs::path(file_for_messages).stem().string());
  read_environment(ctx, sc);
  read_shapes(ctx, sc);
  r.flush_deferred();
  return scene;
}

Scene parse_scene_text(const std::string& text, const std::string& file_for_messages, const std::string& base_dir,
                       const LoadOptions& options) {
  const json j = scene_detail::parse_json_text(text, file_for_messages);
  return parse_scene(j, file_for_messages, base_dir, options);
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
  namespace fs = std::filesystem;
  if (is_gltf_file(path)) return load_gltf_scene(path, options);
  if (options.gltf_camera)
    throw Error("--camera " + std::to_string(*options.gltf_camera) + ": " + path +
                " is not a glTF file (.gltf, .glb); a coursework scene has one camera");
  // Bounded, and only from a regular file: /dev/zero or /dev/urandom as a
  // scene would otherwise be read until memory runs out.
  const std::string text = read_input_file(path, "scene file", limits::kMaxSceneFileBytes);
  fs::path dir = fs::path(path).parent_path();
  return parse_scene_text(text, path, dir.empty() ? std::string(".") : dir.string(), options);
}

Scene load_scene_document(const json& j, const std::string& name, const std::string& base_dir,
                          const LoadOptions& options) {
  Scene scene = parse_scene(j, name, base_dir, options);
  scene.document = j.dump();
  return scene;
}

}  // namespace caustica
