#include "host/lights/light_types.h"

#include <algorithm>
#include <cmath>

#include "host/error.h"
#include "host/math_constants.h"

namespace caustica {

// The registry: one line per light type, in the order of the device's
// LIGHT_TYPES rows (kernels/lib/lights.h), which number the kinds.
#define HOST_LIGHT_TYPES(X) X(point) X(rect) X(sphere) X(triangle) X(cylinder) X(spot) X(environment) X(directional)

#define DECLARE_LIGHT_TYPE(type) LightType type##_light_type();
HOST_LIGHT_TYPES(DECLARE_LIGHT_TYPE)
#undef DECLARE_LIGHT_TYPE

const std::vector<LightType>& light_types() {
  static const std::vector<LightType> types = [] {
#define LIST_LIGHT_TYPE(type) type##_light_type(),
    std::vector<LightType> t = {HOST_LIGHT_TYPES(LIST_LIGHT_TYPE)};
#undef LIST_LIGHT_TYPE
    // A kind's class (delta, area, environment) is the device registry's to say.
#define LIGHT_KIND_CLASS(kind, type, cls) cls,
    const int class_of[] = {LIGHT_TYPES(LIGHT_KIND_CLASS)};
#undef LIGHT_KIND_CLASS
    for (LightType& type : t) {
      const int cls = type.kind < LIGHT_KIND_COUNT ? class_of[type.kind] : -1;
      type.delta = cls == 0;
      type.area = cls == 1;
      type.environment = cls == 2;
    }
    return t;
  }();
  return types;
}

const LightType& light_type(uint32_t kind) {
  const std::vector<LightType>& types = light_types();
  if (kind >= types.size() || types[kind].kind != kind)
    throw Error("internal: light kind " + std::to_string(kind) + " is not in the host's light registry");
  return types[kind];
}

const LightType* light_type_of_file(const std::string& file_type) {
  for (const LightType& t : light_types())
    if (t.file_type && file_type == t.file_type) return &t;
  return nullptr;
}

std::string light_file_types() {
  std::string s;
  for (const LightType& t : light_types())
    if (t.file_type) s += std::string(s.empty() ? "" : ", ") + "\"" + t.file_type + "\"";
  return s;
}

bool has_delta_light(const Scene& scene) {
  for (const Light& l : scene.lights)
    if (light_type(l.kind).delta) return true;
  return false;
}

std::vector<Light> lights_of_kind(const Scene& scene, uint32_t kind) {
  std::vector<Light> out;
  for (const Light& l : scene.lights)
    if (l.kind == kind) out.push_back(l);
  return out;
}

Light light_in_scene(const Scene& scene, uint32_t i) {
  const Light& l = scene.lights.at(i);
  const LightType& type = light_type(l.kind);
  return type.in_scene ? type.in_scene(l, scene) : l;
}

cs_float4 scene_bounding_sphere(const Scene& scene) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  auto grow = [&](const glm::vec3& p, float r) {
    lo = glm::min(lo, p - glm::vec3(r));
    hi = glm::max(hi, p + glm::vec3(r));
  };
  for (const Sphere& s : scene.spheres) grow(to_vec3(s.center_radius), s.center_radius.w);
  for (const Cylinder& c : scene.cylinders) grow(to_vec3(c.center_radius), c.center_radius.w + c.axis_half.w);
  for (const Triangle& t : scene.triangles)
    for (const cs_float4* v : {&t.v0, &t.v1, &t.v2}) grow(to_vec3(*v), 0.0f);
  const bool empty = !(lo.x <= hi.x);
  const glm::vec3 centre = empty ? glm::vec3(0.0f) : 0.5f * (lo + hi);
  const float radius = empty ? 1.0f : std::max(1e-6f, 1.001f * 0.5f * glm::length(hi - lo));
  return to_float4(centre, radius);
}

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

float area_light_power(const Light& l) {
  return ((l.flags & LIGHT_TWO_SIDED) ? 2.0f : 1.0f) * kPiF * l.emitted.w * luminance(to_vec3(l.emitted));
}

LightType shape_light_type(uint32_t kind) {
  LightType t;
  t.kind = kind;
  t.power = area_light_power;
  return t;
}

Light delta_light_at(const glm::vec3& p, const glm::vec3& intensity) {
  Light l{};
  l.kind = LIGHT_POINT;
  l.p0 = to_float4(p);
  l.emitted = to_float4(intensity, 0.0f);
  return l;
}

uint32_t add_emissive_material(Scene& scene, const glm::vec3& radiance) {
  Material m = blank_material();
  m.diffuse = to_float4(glm::vec3(0.0f), 0.0f);
  m.specular = to_float4(glm::vec3(0.0f), 0.0f);
  m.emission = to_float4(radiance);
  m.specular_exponent = 1.0f;
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

LightBounds omnidirectional_bounds(const glm::vec3& lo, const glm::vec3& hi) {
  LightBounds b;
  b.lo = lo;
  b.hi = hi;
  b.cos_o = -1.0f;  // every direction
  b.cos_e = 0.0f;
  return b;
}

LightBounds planar_bounds(const glm::vec3* corners, int count, const glm::vec3& normal, bool two_sided) {
  LightBounds b;
  b.lo = b.hi = corners[0];
  for (int i = 1; i < count; ++i) {
    b.lo = glm::min(b.lo, corners[i]);
    b.hi = glm::max(b.hi, corners[i]);
  }
  const float length = glm::length(normal);
  b.axis = length > 0.0f && std::isfinite(length) ? normal / length : glm::vec3(0.0f, 0.0f, 1.0f);
  b.cos_o = length > 0.0f && std::isfinite(length) ? 1.0f : -1.0f;  // no normal: bound every direction
  b.cos_e = 0.0f;                                                    // a surface emits over its hemisphere
  b.two_sided = two_sided;
  return b;
}

}  // namespace caustica
