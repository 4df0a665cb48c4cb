// Point light, "type": "pointlight" (kernels/lib/lights/point_light.h):
// position and intensity I, radiance I / d^2 at distance d.
#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/scene_reader.h"

namespace caustica {
namespace {

using namespace scene_detail;

void read_point_light(const Reader& r, const json& l, const std::string& path, Scene& scene) {
  r.check_keys(l, path, {"type", "position", "intensity"});
  scene.lights.push_back(
      delta_light_at(r.read_vec3(l, "position", path, Range::Coordinate), r.read_vec3(l, "intensity", path, Range::NonNegative)));
}

float point_light_power(const Light& l) { return 4.0f * kPiF * luminance(to_vec3(l.emitted)); }

// The tree: a point, emitting every way.
LightBounds point_tree_bounds(const Light& l) { return omnidirectional_bounds(to_vec3(l.p0), to_vec3(l.p0)); }

}  // namespace

LightType point_light_type() {
  LightType t;
  t.kind = LIGHT_POINT;
  t.file_type = "pointlight";
  t.read = read_point_light;
  t.power = point_light_power;
  t.whitted_stand_in = light_as_itself;
  t.tree_bounds = point_tree_bounds;
  return t;
}

}  // namespace caustica
