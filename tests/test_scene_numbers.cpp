// Every number a scene file holds, table-driven (issue 38): each numeric
// value of a scene that uses every key of scenes/FORMAT.md (and of the
// repository's own scenes) is replaced in turn by 0, -1, 1e-38, +-1e38,
// 1e39 (beyond a float), a string "NaN" and 1e400 (beyond a double). Each
// case must either be refused with one message that names the file and the
// value's JSON pointer (or the array or object holding it), or load; a
// scene that loads renders, in the mode its numbers are read by, to a
// finite image with no non-finite sample dropped on the way. The keys are
// not listed here: they are the numeric leaves the files hold.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/error.h"
#include "host/scene/load_scene.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using nlohmann::json;

// Every key of FORMAT.md's tables with a number in it, in one scene: the
// camera with a lens, every light type, every shape type, a material with
// every numeric key, a checker texture, an image texture, a mesh with its
// transform, and a sky. Two scenes: a file has either a sky or a
// background colour.
json everything_scene(bool sky) {
  const std::string texture = test::source_dir() + "/textures/tiles.png";
  // A tetrahedron: the mesh keys are the transform's, not the mesh's size.
  const std::string mesh = test::temp_dir() + "/tetrahedron.obj";
  std::ofstream(mesh) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  json material = {{"ks", 0.1},           {"kd", 0.8},         {"ka", 0.2},          {"specularexponent", 20},
                   {"diffusecolor", {0.7, 0.6, 0.5}},           {"specularcolor", {1, 1, 1}},
                   {"isreflective", false}, {"reflectivity", 0.5}, {"isrefractive", false}, {"refractiveindex", 1.0},
                   {"roughness", 0.3},     {"metallic", 0.2}};
  json checker = material;
  checker["texture"] = {{"type", "checkerboard"}, {"color1", {1, 1, 1}}, {"color2", {0.1, 0.1, 0.1}}, {"scale", 4}};
  json textured = material;
  textured["texture"] = texture;
  json glass = {{"type", "dielectric"}, {"ior", 1.5}};
  json emissive = {{"type", "emissive"}, {"color", {1, 0.9, 0.8}}, {"intensity", 2}};
  json emission = material;
  emission["emission"] = {0.5, 0.5, 0.5};
  json scene = {
      {"nbounces", 3},
      {"rendermode", "pathtracer"},
      {"camera",
       {{"type", "thinlens"},
        {"width", 6},
        {"height", 4},
        {"position", {0, 1.5, 6}},
        {"lookAt", {0, 0.5, 0}},
        {"upVector", {0, 1, 0}},
        {"fov", 45},
        {"exposure", 0.5},
        {"aperture", 0.05},
        {"focalDistance", 6}}},
      {"scene",
       {{"ambientlight", {0.1, 0.1, 0.1}},
        {"lightsources",
         {{{"type", "pointlight"}, {"position", {-2, 3, 2}}, {"intensity", {1, 1, 1}}},
          {{"type", "arealight"}, {"position", {0, 3, 0}}, {"u", {0.5, 0, 0}}, {"v", {0, 0, 0.5}},
           {"intensity", {5, 5, 5}}, {"samples", 4}},
          {{"type", "arealight"}, {"position", {1, 3, 0}}, {"size", {0.4, 0.3}}, {"intensity", {5, 5, 5}}},
          {{"type", "arealight"}, {"position", {-1, 3, 0}}, {"width", 0.4}, {"height", 0.3},
           {"u", {1, 0, 0}}, {"v", {0, 0, 1}}, {"intensity", {5, 5, 5}}},
          {{"type", "spherelight"}, {"position", {2, 2, 1}}, {"radius", 0.2}, {"intensity", {3, 3, 3}}},
          {{"type", "spotlight"}, {"position", {0, 4, 2}}, {"direction", {0, -1, -0.3}}, {"intensity", {4, 4, 4}},
           {"inner_cone_angle", 10}, {"outer_cone_angle", 30}},
          {{"type", "directional"}, {"direction", {0.3, -1, -0.2}}, {"intensity", {0.5, 0.5, 0.5}}},
          {{"type", "ambient"}, {"intensity", {0.05, 0.05, 0.05}}}}},
        {"shapes",
         {{{"type", "sphere"}, {"center", {-0.8, 0.5, 0}}, {"radius", 0.5}, {"material", glass}},
          {{"type", "sphere"}, {"center", {0.8, 0.5, 0}}, {"radius", 0.5}, {"material", checker}},
          {{"type", "cylinder"}, {"center", {0, 0.3, -1}}, {"axis", {0, 1, 0}}, {"radius", 0.2}, {"height", 0.3},
           {"material", emission}},
          {{"type", "triangle"}, {"v0", {-3, 0, -2}}, {"v1", {-3, 0, 3}}, {"v2", {3, 0, 3}}, {"uv0", {0, 0}},
           {"uv1", {0, 4}}, {"uv2", {4, 4}}, {"material", textured}},
          {{"type", "rectangle"}, {"v0", {-3, 0, -2}}, {"v1", {3, 0, 3}}, {"v2", {3, 0, -2}}, {"v3", {3, 0.01, -2}},
           {"material", material}},
          {{"type", "rectangle"}, {"corner1", {-2, 0, -3}}, {"corner2", {2, 2, -3}}, {"material", material}},
          {{"type", "box"}, {"min", {1.5, 0, -1}}, {"max", {2, 0.5, -0.5}}, {"rotation", {0, 30, 0}},
           {"material", emissive}},
          {{"type", "mesh"}, {"file", mesh},
           {"transform", {{"translate", {-1.5, 0, -1}}, {"rotate", {0, 45, 0}}, {"scale", 0.3}}}},
          {{"type", "mesh"}, {"file", mesh}, {"transform", {{"scale", {0.2, 0.3, 0.2}}}}}}}}}};
  if (sky)
    scene["scene"]["environment"] = {{"sky", {{"sun_elevation", 30}, {"sun_azimuth", 20}, {"turbidity", 3},
                                              {"resolution", {16, 8}}}},
                                     {"intensity", 0.5},
                                     {"rotate", {0, 10, 0}}};
  else
    scene["scene"]["backgroundcolor"] = {0.1, 0.1, 0.2};
  return scene;
}

// Every numeric leaf: (JSON pointer, the value there).
void numeric_leaves(const json& j, const std::string& at, std::vector<std::string>* out) {
  if (j.is_number()) out->push_back(at);
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) numeric_leaves(it.value(), at + "/" + it.key(), out);
  if (j.is_array())
    for (size_t i = 0; i < j.size(); ++i) numeric_leaves(j[i], at + "/" + std::to_string(i), out);
}

// The value as the file writes it: a number, or text that no number type
// holds ("1e400").
struct BadValue {
  const char* name;
  std::string text;
};
const std::vector<BadValue> kBadValues = {
    {"0", "0"},          {"-1", "-1"},         {"1e-38", "1e-38"}, {"1e38", "1e38"},
    {"-1e38", "-1e38"},  {"1e39", "1e39"},     {"\"NaN\"", "\"NaN\""}, {"1e400", "1e400"}};

// The file's text with the value at `pointer` replaced by `text`.
std::string replaced(const json& scene, const std::string& pointer, const std::string& text) {
  json copy = scene;
  const std::string marker = "\"@@caustica-value@@\"";
  copy[json::json_pointer(pointer)] = "@@caustica-value@@";
  std::string out = copy.dump(1);
  out.replace(out.find(marker), marker.size(), text);
  return out;
}

// "/scene/shapes/3/v1/2" names itself, and its holders down to the shape
// or light ("/scene/shapes/3", "/camera", "/scene/environment"): a message
// names one of them, followed by ':', ' ' or a deeper key ("/scene/shapes/
// 5/corner2: ... corner1 ...").
bool names_value(const std::string& message, const std::string& file, const std::string& pointer) {
  if (message.find(file) == std::string::npos) return false;
  for (std::string p = pointer; !p.empty() && p != "/scene"; p = p.substr(0, p.rfind('/')))
    for (const char* after : {":", " ", "/"})
      if (message.find(p + after) != std::string::npos) return true;
  return false;
}

struct Outcome {
  std::string pointer, value, message;  // message empty: loaded
};

TEST(SceneNumbers, EveryNumericKeyIsReadOrRefusedByName) {
  const std::string dir = test::temp_dir();
  std::vector<std::pair<std::string, json>> scenes = {{"with_sky", everything_scene(true)},
                                                      {"with_background", everything_scene(false)}};
  std::vector<Outcome> loaded;
  size_t cases = 0;
  std::set<std::string> pointers_seen;
  for (const auto& [name, scene] : scenes) {
    std::vector<std::string> pointers;
    numeric_leaves(scene, "", &pointers);
    ASSERT_GT(pointers.size(), 100u);
    {
      std::vector<std::string> warnings;
      LoadOptions o;
      o.warnings = &warnings;
      o.strict = true;  // the scene itself uses only known keys
      const std::string path = dir + "/" + name + ".json";
      std::ofstream(path) << scene.dump(1);
      ASSERT_NO_THROW(load_scene(path, o)) << name;
    }
    for (const std::string& pointer : pointers) {
      if (!pointers_seen.insert(pointer).second) continue;  // the same key in both scenes
      for (const BadValue& bad : kBadValues) {
        ++cases;
        const std::string file = name + "_case" + std::to_string(cases) + ".json";
        const std::string path = dir + "/" + file;
        std::ofstream(path) << replaced(scene, pointer, bad.text);
        std::vector<std::string> warnings;
        LoadOptions o;
        o.warnings = &warnings;
        try {
          load_scene(path, o);
          loaded.push_back({pointer, bad.name, ""});
          loaded.back().message = path;  // rendered below
        } catch (const Error& e) {
          EXPECT_TRUE(names_value(e.what(), file, pointer))
              << pointer << " = " << bad.name << ": the message does not name the value: " << e.what();
          EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        } catch (const std::exception& e) {
          ADD_FAILURE() << pointer << " = " << bad.name << ": not a caustica::Error: " << e.what();
        }
      }
    }
  }
  // The extremes that loaded render to a finite image with nothing
  // non-finite or negative dropped on the way: in path mode, and the huge
  // ones in phong too.
  size_t rendered = 0;
  for (const Outcome& o : loaded) {
    if (o.value != "1e38" && o.value != "-1e38" && o.value != "1e-38") continue;
    // Phong reads the same geometry: its own reading of the huge values.
    const bool huge = o.value != "1e-38";
    for (RenderMode mode : {RenderMode::Path, RenderMode::Phong}) {
      if (mode == RenderMode::Phong && !huge) continue;
      const std::string what = o.pointer + " = " + o.value + (mode == RenderMode::Path ? " (path)" : " (phong)");
      SessionOptions so;
      so.scene_path = o.message;
      so.mode = mode;
      so.device = test::device_spec();
      so.spp = 1;
      so.adaptive = false;
      so.error_estimate = false;
      so.caustics = CausticsMode::Off;
      try {
        auto session = prepare_session(so);
        RenderStats stats;
        const ImageF image = session->renderer->render(&stats);
        test::expect_finite_render(image, session->renderer->film().counts(), what);
        ++rendered;
      } catch (const Error& e) {
        // Refused at render time (a light's power beyond a float): named.
        EXPECT_TRUE(names_value(e.what(), o.message.substr(o.message.rfind('/') + 1), o.pointer))
            << what << ": the message does not name the value: " << e.what();
      }
    }
  }
  std::printf("%zu cases, %zu loaded, %zu renders of their extremes\n", cases, loaded.size(), rendered);
}

}  // namespace
}  // namespace caustica
