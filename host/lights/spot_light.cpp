// Spot light, "type": "spotlight" (kernels/lib/lights/spot_light.h): a
// point light limited to a cone about "direction", full intensity within
// "inner_cone_angle" of it, falling off smoothly (glTF KHR_lights_punctual's
// curve) to nothing at "outer_cone_angle". Angles in degrees from the axis,
// as glTF's (which are radians): 0 <= inner < outer, 0.5 <= outer <= 90,
// defaults 0 and 45.
#include <cmath>

#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/scene_reader.h"

namespace caustica {
namespace {

using namespace scene_detail;

void read_spot_light(const Reader& r, const json& l, const std::string& path, Scene& scene) {
  r.check_keys(l, path, {"type", "position", "direction", "intensity", "inner_cone_angle", "outer_cone_angle"});
  const glm::vec3 position = r.read_vec3(l, "position", path, Range::Coordinate);
  glm::vec3 direction;
  if (!unit_direction(r.read_vec3(l, "direction", path, Range::Any), &direction))
    r.expected(path + "/direction", "a direction of nonzero length", l["direction"]);
  const float inner = r.read_number(l, "inner_cone_angle", path, Range::NonNegative, 0.0f);
  const float outer = r.read_number(l, "outer_cone_angle", path, Range::Positive, 45.0f);
  // The kernels compare cosines in float32: a cone narrower than half a
  // degree (1 - cos < 4e-5, some 600 float steps below 1) would lose its
  // falloff's shape to their rounding, and one below ~0.02 degrees would
  // round shut and emit nothing.
  if (!(outer <= 90.0f && outer >= 0.5f))
    r.expected(path + "/outer_cone_angle", "an angle in degrees from 0.5 to 90", l["outer_cone_angle"]);
  if (!(inner < outer))
    r.fail(path + "/inner_cone_angle", "expected an angle below outer_cone_angle (" + std::to_string(outer) +
                                           " degrees), got " + std::to_string(inner));
  scene.lights.push_back(spot_light_at(position, direction,
                                       r.read_vec3(l, "intensity", path, Range::NonNegative), inner, outer));
}

// Its flux: 2 pi I (integral of the falloff over cos from cos_o to 1) =
// 2 pi I ((1 - cos_i) + (cos_i - cos_o) / 3).
float spot_light_power(const Light& l) {
  const double cos_outer = l.p1.w, cos_inner = l.p2.x;
  const double solid = 2.0 * kPi * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 3.0);
  return float(solid * luminance(to_vec3(l.emitted)));
}

// The tree: a point emitting within its outer cone (theta_o, nothing
// past it).
LightBounds spot_tree_bounds(const Light& l) {
  LightBounds b = omnidirectional_bounds(to_vec3(l.p0), to_vec3(l.p0));
  b.axis = to_vec3(l.p1);
  b.cos_o = l.p1.w;
  b.cos_e = 1.0f;
  return b;
}

}  // namespace

Light spot_light_at(const glm::vec3& position, const glm::vec3& unit_direction, const glm::vec3& intensity,
                    double inner_degrees, double outer_degrees) {
  const double to_radians = kPi / 180.0;
  const double cos_inner = std::cos(inner_degrees * to_radians), cos_outer = std::cos(outer_degrees * to_radians);
  const double half_outer = 0.5 * outer_degrees * to_radians;
  Light s = delta_light_at(position, intensity);
  s.kind = LIGHT_SPOT;
  s.p1 = to_float4(unit_direction, float(cos_outer));
  // 1 - cos(outer) = 2 sin^2(outer / 2): exact for narrow cones.
  s.p2 = cs_float4{float(cos_inner), float(2.0 * std::sin(half_outer) * std::sin(half_outer)), 0.0f, 0.0f};
  return s;
}

LightType spot_light_type() {
  LightType t;
  t.kind = LIGHT_SPOT;
  t.file_type = "spotlight";
  t.read = read_spot_light;
  t.power = spot_light_power;
  t.whitted_stand_in = light_as_itself;
  t.tree_bounds = spot_tree_bounds;
  return t;
}

}  // namespace caustica
