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
#include <unordered_map>

#include "host/error.h"

namespace caustica {

namespace {

using nlohmann::json;

enum class Range { Any, NonNegative, Positive };

const char* range_words(Range r) {
  switch (r) {
    case Range::NonNegative: return "non-negative ";
    case Range::Positive: return "positive ";
    default: return "";
  }
}

// The offending value as the user wrote it, shortened. nlohmann dumps inf/nan
// as `null`, which would be misleading next to "expected a finite number".
std::string describe(const json& v) {
  if (v.is_number_float() && !std::isfinite(v.get<double>())) {
    const double d = v.get<double>();
    return std::isnan(d) ? "nan" : (d > 0 ? "inf" : "-inf");
  }
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

// Holds what every message needs (the file name) and where warnings go; the
// readers below are the only places that check a value's type or range.
class Reader {
 public:
  Reader(std::string file, const LoadOptions& options) : file_(std::move(file)), options_(options) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw Error(file_ + ": " + (path.empty() ? "/" : path) + ": " + message);
  }
  [[noreturn]] void expected(const std::string& path, const std::string& what, const json& got) const {
    fail(path, "expected " + what + ", got " + describe(got));
  }
  void warn(const std::string& path, const std::string& message) const {
    const std::string line = file_ + ": " + (path.empty() ? "/" : path) + ": warning: " + message;
    if (options_.warnings)
      options_.warnings->push_back(line);
    else
      std::cerr << line << "\n";
  }

  // nullptr when `key` is absent; `obj` is known to be an object.
  static const json* find(const json& obj, const char* key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }
  const json& require(const json& obj, const char* key, const std::string& path, const std::string& what) const {
    const json* v = find(obj, key);
    if (!v) fail(path, "required key \"" + std::string(key) + "\" is missing (expected " + what + ")");
    return *v;
  }

  const json& object(const json& v, const std::string& path) const {
    if (!v.is_object()) expected(path, "an object", v);
    return v;
  }
  const json& array(const json& v, const std::string& path) const {
    if (!v.is_array()) expected(path, "an array", v);
    return v;
  }
  std::string string(const json& v, const std::string& path) const {
    if (!v.is_string()) expected(path, "a string", v);
    return v.get<std::string>();
  }
  bool boolean(const json& v, const std::string& path) const {
    if (!v.is_boolean()) expected(path, "true or false", v);
    return v.get<bool>();
  }
  // Finite also in single precision: everything ends up in a float.
  float number(const json& v, const std::string& path, Range range) const {
    const std::string what = std::string("a ") + range_words(range) + "finite number";
    if (!v.is_number()) expected(path, what, v);
    const double d = v.get<double>();
    if (!std::isfinite(d)) expected(path, what, v);
    if (std::fabs(d) > FLT_MAX) expected(path, what + " within single precision (|x| <= 3.4e38)", v);
    if ((range == Range::NonNegative && d < 0) || (range == Range::Positive && !(static_cast<float>(d) > 0)))
      expected(path, what, v);
    return static_cast<float>(d);
  }
  int integer(const json& v, const std::string& path, int lo, int hi) const {
    const std::string what = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!v.is_number()) expected(path, what, v);
    const double d = v.get<double>();  // 1200.0 is accepted as 1200
    if (!std::isfinite(d) || d != std::floor(d) || d < lo || d > hi) expected(path, what, v);
    return static_cast<int>(d);
  }
  glm::vec3 vec3(const json& v, const std::string& path, Range range) const {
    if (!v.is_array() || v.size() != 3)
      expected(path, std::string("an array of 3 ") + range_words(range) + "numbers", v);
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) out[i] = number(v[i], path + "/" + std::to_string(i), range);
    return out;
  }

  // Keyed forms: `fallback` makes the key optional.
  float read_number(const json& obj, const char* key, const std::string& path, Range range,
                    std::optional<float> fallback = std::nullopt) const {
    const std::string p = path + "/" + key;
    if (fallback && !find(obj, key)) return *fallback;
    return number(require(obj, key, p, std::string("a ") + range_words(range) + "finite number"), p, range);
  }
  int read_int(const json& obj, const char* key, const std::string& path, int lo, int hi,
               std::optional<int> fallback = std::nullopt) const {
    const std::string p = path + "/" + key;
    if (fallback && !find(obj, key)) return *fallback;
    return integer(require(obj, key, p, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"), p,
                   lo, hi);
  }
  glm::vec3 read_vec3(const json& obj, const char* key, const std::string& path, Range range,
                      std::optional<glm::vec3> fallback = std::nullopt) const {
    const std::string p = path + "/" + key;
    if (fallback && !find(obj, key)) return *fallback;
    return vec3(require(obj, key, p, std::string("an array of 3 ") + range_words(range) + "numbers"), p, range);
  }
  bool read_bool(const json& obj, const char* key, const std::string& path, bool fallback) const {
    const json* v = find(obj, key);
    return v ? boolean(*v, path + "/" + key) : fallback;
  }
  std::string read_string(const json& obj, const char* key, const std::string& path,
                          std::optional<std::string> fallback = std::nullopt) const {
    const std::string p = path + "/" + key;
    if (fallback && !find(obj, key)) return *fallback;
    return string(require(obj, key, p, "a string"), p);
  }
  const json& read_object(const json& obj, const char* key, const std::string& path) const {
    const std::string p = path + "/" + key;
    return object(require(obj, key, p, "an object"), p);
  }

  const LoadOptions& options() const { return options_; }

 private:
  std::string file_;
  const LoadOptions& options_;
};

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

RenderMode read_mode(const Reader& r, const json& top) {
  const json* v = Reader::find(top, "rendermode");
  std::optional<RenderMode> mode;
  if (v) {
    const std::string name = lower(r.string(*v, "/rendermode"));
    if (name == "binary") mode = RenderMode::Binary;
    else if (name == "phong") mode = RenderMode::Phong;
    else if (name != "pathtracer" && name != "pathtracing" && name != "path")
      r.expected("/rendermode", "one of \"binary\", \"phong\"", *v);
  }
  if (r.options().mode_override) return *r.options().mode_override;
  if (v && !mode)
    r.fail("/rendermode", "path tracing (\"" + v->get<std::string>() +
                              "\") is not supported yet; render with --mode binary|phong instead");
  return mode.value_or(RenderMode::Phong);
}

CameraDesc read_camera(const Reader& r, const json& top) {
  const std::string path = "/camera";
  const json& cam = r.read_object(top, "camera", "");
  const std::string type = r.read_string(cam, "type", path, std::string("pinhole"));
  if (type != "pinhole")
    r.warn(path + "/type", "camera type \"" + type + "\" is not supported yet; rendering it as a pinhole camera");
  CameraDesc c;
  c.width = r.read_int(cam, "width", path, 1, 32768);
  c.height = r.read_int(cam, "height", path, 1, 32768);
  c.position = r.read_vec3(cam, "position", path, Range::Any);
  c.look_at = r.read_vec3(cam, "lookAt", path, Range::Any);
  c.up = r.read_vec3(cam, "upVector", path, Range::Any);
  const std::string fov_what = "a vertical field of view in degrees, 0 < fov < 180";
  const json& fov = r.require(cam, "fov", path + "/fov", fov_what);
  c.fov_y_degrees = r.number(fov, path + "/fov", Range::Any);
  if (!(c.fov_y_degrees > 0.0f && c.fov_y_degrees < 180.0f)) r.expected(path + "/fov", fov_what, fov);
  c.exposure = r.read_number(cam, "exposure", path, Range::Any, 0.0f);
  try {
    camera_basis(c);
  } catch (const Error& e) {
    r.fail(path, e.what());
  }
  return c;
}

std::vector<PointLight> read_lights(const Reader& r, const json& scene) {
  std::vector<PointLight> lights;
  const json* list = Reader::find(scene, "lightsources");
  if (!list) return lights;
  const std::string base = "/scene/lightsources";
  r.array(*list, base);
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string path = base + "/" + std::to_string(i);
    const json& l = r.object((*list)[i], path);
    const char* what = "a light type: \"pointlight\" or \"arealight\"";
    const std::string type = r.string(r.require(l, "type", path + "/type", what), path + "/type");
    if (type == "arealight")
      r.warn(path, "area lights are not supported yet; using a point light at its \"position\"");
    else if (type != "pointlight")
      r.expected(path + "/type", what, l["type"]);
    PointLight p{};
    p.position = to_float4(r.read_vec3(l, "position", path, Range::Any));
    p.intensity = to_float4(r.read_vec3(l, "intensity", path, Range::NonNegative));
    lights.push_back(p);
  }
  return lights;
}

// Materials are stored once: generated scenes repeat a few materials over
// thousands of shapes. Keyed on the bytes, which are fully defined because
// every field (padding included) is written.
class MaterialTable {
 public:
  explicit MaterialTable(std::vector<Material>& out) : out_(out) {}
  cs_uint add(const Material& m) {
    std::string key(reinterpret_cast<const char*>(&m), sizeof m);
    auto [it, inserted] = index_.emplace(std::move(key), static_cast<cs_uint>(out_.size()));
    if (inserted) out_.push_back(m);
    return it->second;
  }

 private:
  std::vector<Material>& out_;
  std::unordered_map<std::string, cs_uint> index_;
};

Material read_material(const Reader& r, const json& shape, const std::string& shape_path) {
  static const json kEmpty = json::object();
  const json* v = Reader::find(shape, "material");
  const std::string path = shape_path + "/material";
  const json& m = v ? r.object(*v, path) : kEmpty;
  Material out{};
  out.diffuse = to_float4(r.read_vec3(m, "diffusecolor", path, Range::NonNegative, glm::vec3(0.8f)),
                          r.read_number(m, "kd", path, Range::NonNegative, 0.9f));
  out.specular = to_float4(r.read_vec3(m, "specularcolor", path, Range::NonNegative, glm::vec3(1.0f)),
                           r.read_number(m, "ks", path, Range::NonNegative, 0.1f));
  out.specular_exponent = r.read_number(m, "specularexponent", path, Range::NonNegative, 20.0f);
  out.reflectivity = r.read_number(m, "reflectivity", path, Range::NonNegative, 1.0f);
  out.ior = r.read_number(m, "refractiveindex", path, Range::Positive, 1.0f);
  out.ka = r.read_number(m, "ka", path, Range::NonNegative, kDefaultAmbient);
  if (r.read_bool(m, "isreflective", path, false)) out.flags |= MATERIAL_REFLECTIVE;
  if (r.read_bool(m, "isrefractive", path, false)) out.flags |= MATERIAL_REFRACTIVE;
  out.texture = -1;
  return out;
}

// Zero (or float-noise) area: sin of the corner angle below ~1e-7.
bool degenerate_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 e1 = glm::dvec3(b) - glm::dvec3(a), e2 = glm::dvec3(c) - glm::dvec3(a);
  const double scale = std::max(glm::dot(e1, e1), glm::dot(e2, e2));
  return !(glm::length(glm::cross(e1, e2)) > 1e-7 * scale);
}

constexpr const char* kShapeTypes = "a shape type: \"sphere\", \"cylinder\" or \"triangle\"";

void read_shapes(const Reader& r, const json& scene, Scene& out) {
  const std::string base = "/scene/shapes";
  const json& shapes = r.array(r.require(scene, "shapes", base, "an array of shapes"), base);
  MaterialTable materials(out.materials);
  constexpr size_t kWarnLimit = 8;  // a broken mesh-like file should not flood the terminal
  size_t dropped = 0;
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::string path = base + "/" + std::to_string(i);
    const json& s = r.object(shapes[i], path);
    const std::string type = r.string(r.require(s, "type", path + "/type", kShapeTypes), path + "/type");
    if (type == "sphere") {
      Sphere sp{};
      sp.center_radius = to_float4(r.read_vec3(s, "center", path, Range::Any),
                                   r.read_number(s, "radius", path, Range::Positive));
      sp.material = materials.add(read_material(r, s, path));
      out.spheres.push_back(sp);
    } else if (type == "cylinder") {
      Cylinder cy{};
      cy.center_radius = to_float4(r.read_vec3(s, "center", path, Range::Any),
                                   r.read_number(s, "radius", path, Range::Positive));
      const glm::dvec3 axis(r.read_vec3(s, "axis", path, Range::Any));
      const double len = glm::length(axis);
      if (!(len > 0.0)) r.expected(path + "/axis", "a direction of nonzero length", s["axis"]);
      cy.axis_half = to_float4(glm::vec3(axis / len), r.read_number(s, "height", path, Range::Positive));
      cy.material = materials.add(read_material(r, s, path));
      out.cylinders.push_back(cy);
    } else if (type == "triangle") {
      const glm::vec3 v0 = r.read_vec3(s, "v0", path, Range::Any);
      const glm::vec3 v1 = r.read_vec3(s, "v1", path, Range::Any);
      const glm::vec3 v2 = r.read_vec3(s, "v2", path, Range::Any);
      const Material m = read_material(r, s, path);  // validated even when the triangle is dropped
      if (degenerate_triangle(v0, v1, v2)) {
        if (++dropped <= kWarnLimit) r.warn(path, "triangle has zero area; dropped");
        continue;
      }
      Triangle t{};
      t.v0 = to_float4(v0);
      t.v1 = to_float4(v1);
      t.v2 = to_float4(v2);
      t.material = materials.add(m);
      out.triangles.push_back(t);
    } else {
      r.expected(path + "/type", kShapeTypes, s["type"]);
    }
  }
  if (dropped > kWarnLimit) r.warn(base, std::to_string(dropped) + " zero-area triangles dropped in total");
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
// carries no position) is reported like any other bad value.
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
    for (const Frame& f : frames_) error_path += "/" + (f.array ? std::to_string(f.index) : f.key);
    return false;
  }

  size_t error_byte = 0;
  int error_id = 0;
  std::string error_token, error_what, error_path;

 private:
  struct Frame {
    bool array;
    size_t index;
    std::string key;
  };
  // A complete value moves the enclosing array on to its next element.
  bool value(bool ok) {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return ok;
  }
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
};

json parse_text(const std::string& text, const std::string& path) {
  json j;
  PathTrackingSax sax(j);
  if (json::sax_parse(text, &sax, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true)) return j;
  const auto [line, column] = line_column(text, sax.error_byte);
  const std::string where = path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
  if (sax.error_id == 406)
    throw Error(where + (sax.error_path.empty() ? "/" : sax.error_path) + ": expected a finite number, got " +
                sax.error_token + " (out of range)");
  throw Error(where + "JSON syntax error: " + parse_reason(sax.error_what));
}

}  // namespace

Scene parse_scene(const json& j, const std::string& file_for_messages, const std::string& base_dir,
                  const LoadOptions& options) {
  (void)base_dir;  // no asset references in the official format yet (textures/meshes come later)
  const Reader r(file_for_messages, options);
  r.object(j, "");
  Scene scene;
  scene.source_path = file_for_messages;
  scene.nbounces = r.read_int(j, "nbounces", "", 0, 1024, 4);
  scene.mode = read_mode(r, j);
  scene.camera = read_camera(r, j);
  const json& sc = r.read_object(j, "scene", "");
  scene.background = r.read_vec3(sc, "backgroundcolor", "/scene", Range::NonNegative, glm::vec3(0.0f));
  scene.point_lights = read_lights(r, sc);
  read_shapes(r, sc, scene);
  return scene;
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw Error(path + ": scene file not found");
  if (ec) throw Error(path + ": cannot access scene file: " + ec.message());
  if (fs::is_directory(st)) throw Error(path + ": is a directory, expected a scene .json file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open scene file: " + std::strerror(errno));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw Error(path + ": error while reading scene file");
  const json j = parse_text(buf.str(), path);
  fs::path dir = fs::path(path).parent_path();
  return parse_scene(j, path, dir.empty() ? std::string(".") : dir.string(), options);
}

}  // namespace caustica
