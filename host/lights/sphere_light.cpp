// Sphere light, "type": "spherelight" (kernels/lib/lights/sphere_light.h):
// centre ("position"), radius and radiance ("intensity") outward. Emissive
// spheres of the scene are sphere lights too (light_table.cpp), without
// geometry of their own.
#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/scene_reader.h"

namespace caustica {
namespace {

using namespace scene_detail;

void read_sphere_light(const Reader& r, const json& l, const std::string& path, Scene& scene) {
  r.check_keys(l, path, {"type", "position", "intensity", "radius", "samples"});
  Light s{};
  s.kind = LIGHT_SPHERE;
  const glm::vec3 centre = r.read_vec3(l, "position", path, Range::Coordinate);
  const float radius = r.read_number(l, "radius", path, Range::Size);
  s.p0 = to_float4(centre, radius);
  s.emitted = to_float4(r.read_vec3(l, "intensity", path, Range::NonNegative), 4.0f * kPiF * radius * radius);
  r.read_int(l, "samples", path, 1, 1 << 20, 1);  // checked; path mode's samples per pixel decide instead
  scene.lights.push_back(s);
}

// Phong: a point light at the centre with the light's intensity.
Light sphere_stand_in(const Light& l) { return delta_light_at(to_vec3(l.p0), to_vec3(l.emitted)); }

void add_sphere_geometry(Scene& scene, uint32_t light_index) {
  const Light l = scene.lights[light_index];
  Sphere s{};
  s.center_radius = l.p0;
  s.material = add_emissive_material(scene, to_vec3(l.emitted));
  scene.light_geometry.prims.push_back({light_index, (PRIM_SPHERE << PRIM_TYPE_SHIFT) | uint32_t(scene.spheres.size())});
  scene.spheres.push_back(s);
}

// The tree: its box, emitting every way.
LightBounds sphere_tree_bounds(const Light& l) {
  const glm::vec3 c = to_vec3(l.p0), r(l.p0.w);
  return omnidirectional_bounds(c - r, c + r);
}

}  // namespace

LightType sphere_light_type() {
  LightType t;
  t.kind = LIGHT_SPHERE;
  t.file_type = "spherelight";
  t.read = read_sphere_light;
  t.power = area_light_power;
  t.whitted_stand_in = sphere_stand_in;
  t.add_geometry = add_sphere_geometry;
  t.tree_bounds = sphere_tree_bounds;
  return t;
}

}  // namespace caustica
