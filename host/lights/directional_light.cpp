// Directional light, "type": "directional" (kernels/lib/lights/
// directional_light.h): a delta light at infinity, glTF KHR_lights_punctual's
// directional light (a sun). "direction" is the way the light travels
// (nonzero, normalised on load); "intensity" is its irradiance E (RGB >= 0)
// on a surface facing it. Both are required: a sun has no natural default.
// The file cannot say how large the scene is, and the device needs it
// (shadow rays aim past the scene, photons cross a disk of it): in_scene
// fills in the scene's bounding sphere when the tables are built
// (light_table.cpp), and the power the light is picked by is the flux
// through that sphere's disk, luminance(E) pi R^2 (the environment light's
// rule: host/lights/environment_light.cpp).
#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/scene_reader.h"

namespace caustica {
namespace {

using namespace scene_detail;

void read_directional_light(const Reader& r, const json& l, const std::string& path, Scene& scene) {
  r.check_keys(l, path, {"type", "direction", "intensity"});
  glm::vec3 direction;
  if (!unit_direction(r.read_vec3(l, "direction", path, Range::Any), &direction))
    r.expected(path + "/direction", "a direction of nonzero length (the way the light travels)", l["direction"]);
  scene.lights.push_back(
      directional_light_along(direction, r.read_vec3(l, "intensity", path, Range::NonNegative)));
}

float directional_light_power(const Light& l) {
  const double r = l.p0.w;
  return float(kPi * r * r * luminance(to_vec3(l.emitted)));
}

Light with_scene_bounds(const Light& l, const Scene& scene) {
  Light placed = l;
  placed.p0 = scene_bounding_sphere(scene);
  return placed;
}

}  // namespace

Light directional_light_along(const glm::vec3& unit_direction, const glm::vec3& irradiance) {
  Light l{};
  l.kind = LIGHT_DIRECTIONAL;
  l.p1 = to_float4(unit_direction, 0.0f);
  l.emitted = to_float4(irradiance, 0.0f);
  return l;
}

LightType directional_light_type() {
  LightType t;
  t.kind = LIGHT_DIRECTIONAL;
  t.file_type = "directional";
  t.read = read_directional_light;
  t.power = directional_light_power;
  t.whitted_stand_in = light_as_itself;
  t.in_scene = with_scene_bounds;
  return t;
}

}  // namespace caustica
