// The light types on the host: one file per type (host/lights/<type>_light.cpp)
// and one registry (light_types.cpp), the device's
// (kernels/lib/lights.h) in mirror.
//
// Rules: the scene keeps its lights in the one form the device reads
// (Light, kernels/shared/types.h), as the file wrote them; a type's host
// file says how a scene file writes it (read), how much it emits (power:
// the pick probability's weight), what phong shades in its place (a delta
// light) and what geometry path mode adds so that BSDF-sampled rays hit
// it. Types made only from emissive shapes (triangles, cylinders) have no
// file form and no stand-in; the environment is the scene object's
// "environment" (environment_light.h), with no stand-in either.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/scene/scene.h"
#include "lib/lights.h"

namespace caustica {

namespace scene_detail {
class Reader;
}

// What the light tree (host/lights/light_tree.h) knows of a light: the
// box its emitting points lie in and the cone of its emission, an axis
// with cos theta_o (how far the normals spread about it) and cos theta_e
// (how far past a normal it emits: 0 for a surface, pi/2 past it), both
// sides of it for a two-sided surface. Power is the light table's.
struct LightBounds {
  glm::vec3 lo{0.0f}, hi{0.0f};
  glm::vec3 axis{0.0f, 0.0f, 1.0f};
  float cos_o = 1.0f, cos_e = 0.0f;
  bool two_sided = false;
};
// An omnidirectional emitter in the box [lo, hi] (point, sphere,
// cylinder lights) and a one-sided planar one with these corners.
LightBounds omnidirectional_bounds(const glm::vec3& lo, const glm::vec3& hi);
LightBounds planar_bounds(const glm::vec3* corners, int count, const glm::vec3& normal, bool two_sided);

struct LightType {
  uint32_t kind = 0;             // the device registry's row (LIGHT_POINT, ...)
  const char* file_type = nullptr;  // "type" in a scene file's lightsources; nullptr: made from shapes only
  // The device's LIGHT_TYPES row's class, set by the registry: a delta
  // light has no surface (reached by next-event estimation and photons
  // only); an area light is a surface of the scene; the environment is
  // the sky, reached by rays that leave the scene.
  bool delta = false;
  bool area = false;
  bool environment = false;
  // Appends the light written at `path` (an object whose "type" is file_type) to scene.lights.
  void (*read)(const scene_detail::Reader& r, const nlohmann::json& light, const std::string& path,
               Scene& scene) = nullptr;
  float (*power)(const Light& l) = nullptr;  // luminance-weighted flux
  // Phong's delta light in its place (point, spot and directional lights:
  // themselves, light_as_itself).
  Light (*whitted_stand_in)(const Light& l) = nullptr;
  // Path mode: appends the light's own geometry to the scene (with an
  // emissive material that reflects nothing) and names it in
  // scene.light_geometry; nullptr for delta lights and shape lights.
  void (*add_geometry)(Scene& scene, uint32_t light_index) = nullptr;
  // The light as the device reads it, given the scene it lights: what the
  // file cannot say (the directional light: the scene's bounding sphere,
  // which its shadow rays and photons need). nullptr: the light as read.
  // The tables (light_table.cpp) apply it before power and stand-in.
  Light (*in_scene)(const Light& l, const Scene& scene) = nullptr;
  // The light tree's bounds (LightBounds above); nullptr for lights at
  // infinity (directional, environment), which the tree leaves out.
  LightBounds (*tree_bounds)(const Light& l) = nullptr;
};

// The Whitted stand-in of a light that is its own (a delta light).
inline Light light_as_itself(const Light& l) { return l; }

const std::vector<LightType>& light_types();  // in kind order
const LightType& light_type(uint32_t kind);
const LightType* light_type_of_file(const std::string& file_type);  // nullptr: no such type
// "\"pointlight\", \"arealight\", ..." for error messages.
std::string light_file_types();

// Does the scene have a delta light (point, spot, directional: reached
// only by next-event estimation and photons)?
bool has_delta_light(const Scene& scene);
// The scene's lights of one kind, in file order.
std::vector<Light> lights_of_kind(const Scene& scene, uint32_t kind);

// Scene::lights[i] as the device reads it (LightType::in_scene).
Light light_in_scene(const Scene& scene, uint32_t i);
// A sphere bounding every shape of the scene (xyz centre, w radius), a
// little beyond its box's half diagonal so that a disk of it covers the
// scene whole; the unit sphere about the origin for an empty scene. Lights
// at infinity shoot shadow rays past it and photons across it.
cs_float4 scene_bounding_sphere(const Scene& scene);

// Helpers the type files share.
float luminance(const glm::vec3& c);
// An area light's flux: pi * area * luminance(radiance), twice for a
// two-sided one.
float area_light_power(const Light& l);
// A type made only from emissive shapes: no file form, no stand-in, no
// geometry of its own; the area light's power.
LightType shape_light_type(uint32_t kind);
// A point light at p with intensity i.
Light delta_light_at(const glm::vec3& p, const glm::vec3& intensity);
// A spot light (spot_light.cpp) with cone angles in degrees from its axis;
// the caller has checked 0 <= inner < outer and 0.5 <= outer <= 90.
Light spot_light_at(const glm::vec3& position, const glm::vec3& unit_direction, const glm::vec3& intensity,
                    double inner_degrees, double outer_degrees);
// A directional light (directional_light.cpp) travelling along
// unit_direction with irradiance E; its scene bounds are filled in later
// (LightType::in_scene).
Light directional_light_along(const glm::vec3& unit_direction, const glm::vec3& irradiance);
// An emissive material that reflects nothing, appended to the scene.
uint32_t add_emissive_material(Scene& scene, const glm::vec3& radiance);

}  // namespace caustica
