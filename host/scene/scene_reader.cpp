// The checked JSON readers shared by the loader's parts (scene_reader.h).
#include "host/scene/scene_reader.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <iostream>

#include "host/error.h"
#include "host/limits.h"

namespace caustica {

namespace scene_detail {

const char* range_words(Range r) {
  switch (r) {
    case Range::NonNegative: return "non-negative ";
    case Range::Positive: return "positive ";
    case Range::Reflectance: return "non-negative ";  // and at most kMaxReflectance: its own message
    case Range::Size: return "positive ";              // and at most kMaxSceneCoordinate: its own message
    case Range::Extent: return "non-negative ";
    default: return "";
  }
}

namespace {

// Writes v compactly into out, stopping once out is longer than `limit`: a
// value may be a 100 MB array or nested 10^5 levels deep (nlohmann's dump
// recurses once per level), and only its first characters are shown. Each
// level writes at least one character, so the recursion is as deep as
// `limit` at most.
void describe_into(const json& v, std::string& out, size_t limit) {
  if (out.size() > limit) return;
  if (v.is_object()) {
    out += '{';
    bool first = true;
    for (auto it = v.begin(); it != v.end() && out.size() <= limit; ++it) {
      if (!first) out += ',';
      first = false;
      describe_into(json(it.key()), out, limit);
      out += ':';
      describe_into(it.value(), out, limit);
    }
    out += '}';
  } else if (v.is_array()) {
    out += '[';
    for (size_t i = 0; i < v.size() && out.size() <= limit; ++i) {
      if (i) out += ',';
      describe_into(v[i], out, limit);
    }
    out += ']';
  } else if (v.is_number_float() && !std::isfinite(v.get<double>())) {
    // nlohmann dumps inf/nan as `null`, which would be misleading next to
    // "expected a finite number".
    const double d = v.get<double>();
    out += std::isnan(d) ? "nan" : (d > 0 ? "inf" : "-inf");
  } else if (v.is_string() && v.get_ref<const std::string&>().size() > limit) {
    out += json(v.get_ref<const std::string&>().substr(0, limit)).dump(-1, ' ', false, json::error_handler_t::replace);
  } else {
    out += v.dump(-1, ' ', false, json::error_handler_t::replace);
  }
}

}  // namespace

std::string describe(const json& v) {
  std::string s;
  describe_into(v, s, 60);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

void Reader::fail(const std::string& path, const std::string& message) const {
  throw Error(file_ + ": " + (path.empty() ? "/" : path) + ": " + message);
}

void Reader::expected(const std::string& path, const std::string& what, const json& got) const {
  fail(path, "expected " + what + ", got " + describe(got));
}

void Reader::forward_warning(const std::string& line) const {
  if (options_.warnings)
    options_.warnings->push_back(line);
  else
    std::cerr << line << "\n";
}

void Reader::warn(const std::string& path, const std::string& message) const {
  forward_warning(file_ + ": " + (path.empty() ? "/" : path) + ": warning: " + message);
}

void Reader::warn_once(const std::string& group, const std::string& path, const std::string& message) const {
  auto [it, inserted] = deferred_index_.emplace(group, deferred_.size());
  if (inserted)
    deferred_.push_back(Deferred{path, message, 0});
  else
    ++deferred_[it->second].more;
}

void Reader::flush_deferred() const {
  for (const Deferred& d : deferred_)
    warn(d.path, d.message + (d.more ? " (and " + std::to_string(d.more) + " more like it)" : ""));
  deferred_.clear();
  deferred_index_.clear();
}

// Array indices become "*" so that one key repeated on every shape is one
// group of warnings.
static std::string path_pattern(const std::string& path) {
  std::string out;
  size_t i = 0;
  while (i < path.size()) {
    const size_t next = path.find('/', i + 1);
    const std::string seg = path.substr(i, next == std::string::npos ? std::string::npos : next - i);
    const bool index = seg.size() > 1 && std::all_of(seg.begin() + 1, seg.end(), [](char c) { return c >= '0' && c <= '9'; });
    out += index ? "/*" : seg;
    if (next == std::string::npos) break;
    i = next;
  }
  return out;
}

void Reader::check_keys(const json& obj, const std::string& path, const KeyList& known, const KeyList& also) const {
  auto in = [](const KeyList& list, const std::string& k) {
    return std::any_of(list.begin(), list.end(), [&](const char* x) { return k == x; });
  };
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if ((!k.empty() && k[0] == '_') || in(known, k) || in(also, k)) continue;
    const std::string p = path + "/" + pointer_token(k);
    if (options_.strict) {
      std::string list;
      for (const KeyList* l : {&known, &also})
        for (const char* x : *l) list += (list.empty() ? "\"" : ", \"") + std::string(x) + "\"";
      fail(p, "expected one of the keys " + list + " (strict mode: unknown keys are errors), got \"" + k + "\"");
    }
    warn_once("key " + path_pattern(p), p, "unknown key \"" + k + "\" ignored");
  }
}

const json* Reader::find_any(const json& obj, const KeyList& keys, const char** which) {
  for (const char* k : keys)
    if (const json* v = find(obj, k)) {
      if (which) *which = k;
      return v;
    }
  return nullptr;
}

const json& Reader::require(const json& obj, const char* key, const std::string& path, const std::string& what) const {
  const json* v = find(obj, key);
  if (!v) fail(path, "required key \"" + std::string(key) + "\" is missing (expected " + what + ")");
  return *v;
}

const json& Reader::object(const json& v, const std::string& path) const {
  if (!v.is_object()) expected(path, "an object", v);
  return v;
}
const json& Reader::array(const json& v, const std::string& path) const {
  if (!v.is_array()) expected(path, "an array", v);
  return v;
}
std::string Reader::string(const json& v, const std::string& path) const {
  if (!v.is_string()) expected(path, "a string", v);
  return v.get<std::string>();
}
bool Reader::boolean(const json& v, const std::string& path) const {
  if (!v.is_boolean()) expected(path, "true or false", v);
  return v.get<bool>();
}
float Reader::number(const json& v, const std::string& path, Range range) const {
  const std::string what = std::string("a ") + range_words(range) + "finite number";
  if (!v.is_number()) expected(path, what, v);
  const double d = v.get<double>();
  if (!std::isfinite(d)) expected(path, what, v);
  if (std::fabs(d) > FLT_MAX) expected(path, what + " within single precision (|x| <= 3.4e38)", v);
  if (((range == Range::NonNegative || range == Range::Reflectance || range == Range::Extent) && d < 0) ||
      ((range == Range::Positive || range == Range::Size) && !(static_cast<float>(d) > 0)))
    expected(path, what, v);
  // Squared and cubed in the kernels: within the scene's coordinate limit.
  if ((range == Range::Coordinate || range == Range::Size || range == Range::Extent) &&
      std::fabs(d) > limits::kMaxSceneCoordinate)
    expected(path,
             what + " within " + std::string(range == Range::Coordinate ? "+-" : "") +
                 "1e12 scene units (the coordinate limit: distances squared and cubed must fit a "
                 "float; scale the scene down)",
             v);
  // A reflectance far above 1 is a typo or a unit mistake; one of 1e29 made
  // every other value of the image meaningless (issue 24).
  if (range == Range::Reflectance && d > limits::kMaxReflectance)
    expected(path,
             "a reflectance in [0, " + std::to_string(int(limits::kMaxReflectance)) +
                 "] (1 reflects all the light that arrives; light comes from emission and lights)",
             v);
  return static_cast<float>(d);
}
int Reader::integer(const json& v, const std::string& path, int lo, int hi) const {
  const std::string what = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!v.is_number()) expected(path, what, v);
  const double d = v.get<double>();  // 1200.0 is accepted as 1200
  if (!std::isfinite(d) || d != std::floor(d) || d < lo || d > hi) expected(path, what, v);
  return static_cast<int>(d);
}
glm::vec3 Reader::vec3(const json& v, const std::string& path, Range range) const {
  if (!v.is_array() || v.size() != 3)
    expected(path, std::string("an array of 3 ") + range_words(range) + "numbers", v);
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = number(v[i], path + "/" + std::to_string(i), range);
  return out;
}
glm::vec2 Reader::vec2(const json& v, const std::string& path, Range range) const {
  if (!v.is_array() || v.size() != 2)
    expected(path, std::string("an array of 2 ") + range_words(range) + "numbers", v);
  glm::vec2 out;
  for (int i = 0; i < 2; ++i) out[i] = number(v[i], path + "/" + std::to_string(i), range);
  return out;
}

float Reader::read_number(const json& obj, const char* key, const std::string& path, Range range,
                          std::optional<float> fallback) const {
  const std::string p = path + "/" + key;
  if (fallback && !find(obj, key)) return *fallback;
  return number(require(obj, key, p, std::string("a ") + range_words(range) + "finite number"), p, range);
}
int Reader::read_int(const json& obj, const char* key, const std::string& path, int lo, int hi,
                     std::optional<int> fallback) const {
  const std::string p = path + "/" + key;
  if (fallback && !find(obj, key)) return *fallback;
  return integer(require(obj, key, p, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"), p,
                 lo, hi);
}
glm::vec3 Reader::read_vec3(const json& obj, const char* key, const std::string& path, Range range,
                            std::optional<glm::vec3> fallback) const {
  const std::string p = path + "/" + key;
  if (fallback && !find(obj, key)) return *fallback;
  return vec3(require(obj, key, p, std::string("an array of 3 ") + range_words(range) + "numbers"), p, range);
}
bool Reader::read_bool(const json& obj, const char* key, const std::string& path, bool fallback) const {
  const json* v = find(obj, key);
  return v ? boolean(*v, path + "/" + key) : fallback;
}
std::string Reader::read_string(const json& obj, const char* key, const std::string& path,
                                std::optional<std::string> fallback) const {
  const std::string p = path + "/" + key;
  if (fallback && !find(obj, key)) return *fallback;
  return string(require(obj, key, p, "a string"), p);
}
const json& Reader::read_object(const json& obj, const char* key, const std::string& path) const {
  const std::string p = path + "/" + key;
  return object(require(obj, key, p, "an object"), p);
}

cs_uint MaterialTable::add(const Material& m) {
  std::string key(reinterpret_cast<const char*>(&m), sizeof m);
  auto [it, inserted] = index_.emplace(std::move(key), static_cast<cs_uint>(out_.size()));
  if (inserted) out_.push_back(m);
  return it->second;
}

}  // namespace scene_detail

}  // namespace caustica
