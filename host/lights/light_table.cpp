#include "host/lights/light_table.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "host/error.h"
#include "host/lights/environment_light.h"
#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/textures.h"

namespace caustica {
namespace {

float max3(const glm::vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }

// The file's lights by kind, then in file order: the pick order (and so
// the images) of the versions that kept one list per kind.
std::vector<uint32_t> lights_by_kind(const Scene& scene) {
  std::vector<uint32_t> order(scene.lights.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return scene.lights[a].kind < scene.lights[b].kind; });
  return order;
}

}  // namespace

void add_light_geometry(Scene& scene) {
  if (scene.light_geometry.added) return;
  scene.light_geometry.added = true;
  for (uint32_t i : lights_by_kind(scene)) {
    const LightType& type = light_type(scene.lights[i].kind);
    if (type.add_geometry) type.add_geometry(scene, i);
  }
}

// A light in messages: where the file wrote it, else its index.
std::string light_name(const Scene& scene, size_t i) {
  if (i < scene.light_sources.size() && !scene.light_sources[i].empty()) return scene.light_sources[i];
  return "light " + std::to_string(i);
}

LightTable build_light_table(const Scene& scene) {
  LightTable t;
  t.light_of_sphere.assign(scene.spheres.size(), LIGHT_NONE);
  t.light_of_cylinder.assign(scene.cylinders.size(), LIGHT_NONE);
  t.light_of_triangle.assign(scene.triangles.size(), LIGHT_NONE);
  std::vector<float> power;
  // mean_texel: an emission texture's mean, which scales the power the
  // light is picked by (its flux exactly when the texture covers the
  // triangle once; otherwise an estimate, > 0 wherever the light emits, so
  // the estimators stay unbiased).
  // A light that emits nothing is left out; one whose power overflows a
  // float (a directional light or a sky over a scene ~1e19 across, an
  // emissive shape of 1e30 area) cannot be picked in proportion to it, and
  // is refused: leaving it out would render the scene unlit without a word.
  auto add = [&](Light l, const glm::vec3& mean_texel_of_texture = glm::vec3(1.0f), const std::string& what = "") {
    const LightType& type = light_type(l.kind);
    Light mean = l;
    mean.emitted = to_float4(to_vec3(l.emitted) * mean_texel_of_texture, l.emitted.w);
    const float p = type.power(mean);
    if (std::isnan(p) || std::isinf(p))
      throw Error(scene.source_path + ": " + what + ": its power (the flux it is sampled by) overflows a 32-bit float" +
                  (l.kind == LIGHT_DIRECTIONAL || l.kind == LIGHT_ENVIRONMENT
                       ? " (a directional light's and a sky's grow with the scene's extent squared)"
                       : "") +
                  ": scale the scene, or its emission, down");
    if (!(p > 0.0f)) return false;
    t.lights.push_back(l);
    power.push_back(p);
    return true;
  };
  // The file's lights; the primitives of their geometry find them.
  const Scene::LightGeometry& g = scene.light_geometry;
  std::vector<uint32_t> table_index(scene.lights.size(), LIGHT_NONE);
  for (uint32_t i : lights_by_kind(scene)) {
    const LightType& type = light_type(scene.lights[i].kind);
    if (!type.delta && !g.added) continue;  // an area light without its geometry: not sampled
    if (add(light_in_scene(scene, i), glm::vec3(1.0f), light_name(scene, i)))
      table_index[i] = uint32_t(t.lights.size() - 1);
  }
  std::vector<bool> geometry_sphere(scene.spheres.size(), false), geometry_triangle(scene.triangles.size(), false);
  for (const Scene::LightPrimitive& p : g.prims) {
    const uint32_t type = p.prim >> PRIM_TYPE_SHIFT, index = p.prim & PRIM_INDEX_MASK;
    std::vector<uint32_t>& of = type == PRIM_SPHERE ? t.light_of_sphere : type == PRIM_CYLINDER ? t.light_of_cylinder
                                                                                                  : t.light_of_triangle;
    of[index] = table_index[p.light];
    if (type == PRIM_SPHERE) geometry_sphere[index] = true;
    if (type == PRIM_TRIANGLE) geometry_triangle[index] = true;
  }
  // Emissive shapes of the file: one light of `kind` with corners p0..p2
  // and `area` per emissive shape. A triangle whose material has an
  // emission texture (glTF's; only triangles have one) names itself and
  // the texture (kernels/lib/lights/triangle_light.h).
  std::map<int, glm::vec3> texture_means;
  auto add_shape = [&](uint32_t material, uint32_t kind, cs_float4 p0, cs_float4 p1, cs_float4 p2, float area,
                       std::vector<uint32_t>& index_of_shape, size_t shape) {
    const Material& m = scene.materials[material];
    const glm::vec3 e = to_vec3(m.emission);
    if (!(max3(e) > 0.0f)) return;
    const bool two_sided = kind == LIGHT_TRIANGLE && (m.flags & MATERIAL_TWO_SIDED);
    Light l{};
    l.kind = kind;
    l.p0 = p0;
    l.p1 = p1;
    l.p2 = p2;
    l.flags = two_sided ? LIGHT_TWO_SIDED : 0u;
    l.emitted = to_float4(e, area);
    glm::vec3 mean(1.0f);
    // Cut-out emitters: only the points that are there emit (kernels/lib/lights.h).
    if (kind == LIGHT_TRIANGLE && (m.flags & (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND))) {
      l.flags |= LIGHT_ALPHA;
      l.p0.w = as_float(uint32_t(shape));
    }
    if (kind == LIGHT_TRIANGLE && m.emission_texture >= 0 && size_t(m.emission_texture) < scene.textures.size()) {
      l.flags |= LIGHT_EMISSION_TEXTURE;
      l.p0.w = as_float(uint32_t(shape));
      l.p1.w = as_float(uint32_t(m.emission_texture));
      auto it = texture_means.find(m.emission_texture);
      if (it == texture_means.end()) it = texture_means.emplace(m.emission_texture, mean_texel(scene, m.emission_texture)).first;
      mean = it->second;
    }
    if (add(l, mean, "the emissive shape " + std::to_string(shape) + " (emission times area)"))
      index_of_shape[shape] = uint32_t(t.lights.size() - 1);
  };
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    if (geometry_triangle[i]) continue;
    const Triangle& tri = scene.triangles[i];
    const glm::vec3 a = to_vec3(tri.v0), b = to_vec3(tri.v1), c = to_vec3(tri.v2);
    add_shape(tri.material, LIGHT_TRIANGLE, tri.v0, tri.v1, tri.v2, 0.5f * glm::length(glm::cross(b - a, c - a)),
              t.light_of_triangle, i);
  }
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    if (geometry_sphere[i]) continue;
    const float r = scene.spheres[i].center_radius.w;
    add_shape(scene.spheres[i].material, LIGHT_SPHERE, scene.spheres[i].center_radius, {}, {}, 4.0f * kPiF * r * r,
              t.light_of_sphere, i);
  }
  for (size_t i = 0; i < scene.cylinders.size(); ++i) {
    const Cylinder& c = scene.cylinders[i];
    const float r = c.center_radius.w, h = c.axis_half.w;
    add_shape(c.material, LIGHT_CYLINDER, c.center_radius, c.axis_half, {}, 4.0f * kPiF * r * h + 2.0f * kPiF * r * r,
              t.light_of_cylinder, i);
  }
  if (scene.environment && add(environment_light(scene), glm::vec3(1.0f), "the environment"))
    t.environment = uint32_t(t.lights.size() - 1);
  set_selection(t.lights, power);
  t.power = power;
  return t;
}

void set_selection(std::vector<Light>& lights, const std::vector<float>& power) {
  double total = 0.0;
  for (float p : power) total += p;
  double prefix = 0.0;
  for (size_t i = 0; i < lights.size(); ++i) {
    lights[i].select_probability = float(power[i] / total);
    prefix += power[i] / total;
    lights[i].select_cdf = i + 1 == lights.size() ? 1.0f : float(prefix);
  }
}

std::vector<Light> whitted_lights(const Scene& scene) {
  std::vector<Light> lights;
  for (uint32_t i : lights_by_kind(scene)) {
    const LightType& type = light_type(scene.lights[i].kind);
    if (type.whitted_stand_in) lights.push_back(type.whitted_stand_in(light_in_scene(scene, i)));
  }
  return lights;
}

std::vector<Light> phong_photon_lights(const Scene& scene) {
  std::vector<Light> lights = whitted_lights(scene);
  if (scene.environment) lights.push_back(environment_light(scene));
  // As build_light_table: a power that overflows is refused, not dropped.
  for (size_t i = 0; i < lights.size(); ++i) {
    const float p = light_type(lights[i].kind).power(lights[i]);
    if (std::isnan(p) || std::isinf(p))
      throw Error(scene.source_path + ": " +
                  (lights[i].kind == LIGHT_ENVIRONMENT ? std::string("the environment")
                                                       : light_name(scene, i)) +
                  ": its photon power overflows a 32-bit float (a sky's grows with the scene's extent squared): "
                  "scale the scene, or its emission, down");
  }
  return emitting_lights(lights);
}

std::vector<Light> emitting_lights(const std::vector<Light>& lights) {
  std::vector<Light> out;
  std::vector<float> power;
  for (const Light& l : lights) {
    const float p = light_type(l.kind).power(l);
    if (!(p > 0.0f) || !std::isfinite(p)) continue;
    out.push_back(l);
    power.push_back(p);
  }
  set_selection(out, power);
  return out;
}

}  // namespace caustica
