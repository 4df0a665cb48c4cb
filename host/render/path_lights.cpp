#include "host/render/path_lights.h"

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

constexpr float kPi = 3.14159265358979f;

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
float max3(const glm::vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }

uint32_t emissive_material(Scene& scene, const glm::vec3& radiance) {
  Material m{};
  m.diffuse = to_float4(glm::vec3(0.0f), 0.0f);
  m.specular = to_float4(glm::vec3(0.0f), 0.0f);
  m.emission = to_float4(radiance);
  m.specular_exponent = 1.0f;
  m.ior = 1.0f;
  m.texture = -1;
  m.roughness = -1.0f;
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

void add_triangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
  Triangle t{};
  t.v0 = to_float4(a);
  t.v1 = to_float4(b);
  t.v2 = to_float4(c);
  t.material = material;
  scene.triangles.push_back(t);
  if (!scene.triangle_shading.empty()) {  // a parallel array when present
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    TriangleShading s{};
    s.n0 = s.n1 = s.n2 = to_float4(n);
    s.u1 = 1.0f;
    s.v2 = 1.0f;
    scene.triangle_shading.push_back(s);
  }
}

}  // namespace

void add_light_geometry(Scene& scene) {
  if (scene.light_geometry.added) return;
  scene.light_geometry.added = true;
  scene.light_geometry.first_triangle = scene.triangles.size();
  scene.light_geometry.first_sphere = scene.spheres.size();
  for (const AreaLightDesc& l : scene.area_lights) {
    const uint32_t m = emissive_material(scene, l.intensity);
    const glm::vec3 a = l.center - 0.5f * l.u - 0.5f * l.v, b = l.center + 0.5f * l.u - 0.5f * l.v,
                    c = l.center + 0.5f * l.u + 0.5f * l.v, d = l.center - 0.5f * l.u + 0.5f * l.v;
    add_triangle(scene, a, b, c, m);  // counter-clockwise about cross(u, v): the emitting side
    add_triangle(scene, a, c, d, m);
  }
  for (const SphereLightDesc& l : scene.sphere_lights) {
    Sphere s{};
    s.center_radius = to_float4(l.center, l.radius);
    s.material = emissive_material(scene, l.intensity);
    scene.spheres.push_back(s);
  }
}

PathLightTable build_path_lights(const Scene& scene) {
  PathLightTable t;
  t.light_of_sphere.assign(scene.spheres.size(), LIGHT_NONE);
  t.light_of_cylinder.assign(scene.cylinders.size(), LIGHT_NONE);
  t.light_of_triangle.assign(scene.triangles.size(), LIGHT_NONE);
  std::vector<float> power;
  auto add = [&](PathLight l, float p, const glm::vec3& emitted) {
    if (!(p > 0.0f) || !std::isfinite(p)) return false;
    l.emitted.x = emitted.x;
    l.emitted.y = emitted.y;
    l.emitted.z = emitted.z;
    t.lights.push_back(l);
    power.push_back(p);
    // The film's scale (PathIntegrator's pass bound) must resolve what a
    // pixel gathers, not the rare sample that hits a light far smaller than
    // a pixel: such a light puts at most its intensity (radiance x area) /
    // d^2 into a pixel's mean, so it counts as the same power spread over a
    // light 1e-3 of its distance d from the camera across (a pixel of a
    // 1000-pixel-wide, ~60 degree view). Trade-off: a camera ray that hits
    // the tiny light itself may exceed the film's range and is clamped and
    // counted (probability ~ its share of the pixel); before, a 1e-6 light
    // of radiance 1e12 left the film a resolution of 1/16 and rounded every
    // ordinary contribution to 0 (stiff_light_limits).
    float radiance = max3(emitted);
    if (l.kind != LIGHT_POINT) {
      const float d = std::max(1e-30f, glm::length(to_vec3(l.p0) - scene.camera.position));
      const float reference = 1e-6f * d * d;
      if (l.emitted.w < reference) radiance *= l.emitted.w / reference;
    }
    t.max_radiance = std::max(t.max_radiance, radiance);
    return true;
  };
  for (const PointLightDesc& p : scene.point_lights) {
    PathLight l{};
    l.kind = LIGHT_POINT;
    l.p0 = to_float4(p.position);
    add(l, 4.0f * kPi * luminance(p.intensity), p.intensity);
  }
  const Scene::LightGeometry& g = scene.light_geometry;
  if (g.added) {
    for (size_t k = 0; k < scene.area_lights.size(); ++k) {
      const AreaLightDesc& a = scene.area_lights[k];
      PathLight l{};
      l.kind = LIGHT_RECT;
      l.p0 = to_float4(a.center);
      l.p1 = to_float4(a.u);
      l.p2 = to_float4(a.v);
      const float area = glm::length(glm::cross(a.u, a.v));
      l.emitted.w = area;
      if (add(l, kPi * area * luminance(a.intensity), a.intensity)) {
        t.light_of_triangle[g.first_triangle + 2 * k] = uint32_t(t.lights.size() - 1);
        t.light_of_triangle[g.first_triangle + 2 * k + 1] = uint32_t(t.lights.size() - 1);
      }
    }
    for (size_t k = 0; k < scene.sphere_lights.size(); ++k) {
      const SphereLightDesc& s = scene.sphere_lights[k];
      PathLight l{};
      l.kind = LIGHT_SPHERE;
      l.p0 = to_float4(s.center, s.radius);
      const float area = 4.0f * kPi * s.radius * s.radius;
      l.emitted.w = area;
      if (add(l, kPi * area * luminance(s.intensity), s.intensity))
        t.light_of_sphere[g.first_sphere + k] = uint32_t(t.lights.size() - 1);
    }
  }
  // Emissive shapes of the file (the light geometry above has its lights):
  // one light of `kind` with corners p0..p2 and `area` per emissive shape.
  auto add_shape = [&](uint32_t material, uint32_t kind, cs_float4 p0, cs_float4 p1, cs_float4 p2, float area,
                       std::vector<uint32_t>& index_of_shape, size_t shape) {
    const glm::vec3 e = to_vec3(scene.materials[material].emission);
    if (!(max3(e) > 0.0f)) return;
    const bool two_sided = kind == LIGHT_TRIANGLE && (scene.materials[material].flags & MATERIAL_TWO_SIDED);
    PathLight l{};
    l.kind = kind;
    l.p0 = p0;
    l.p1 = p1;
    l.p2 = p2;
    l.flags = two_sided ? LIGHT_TWO_SIDED : 0u;
    l.emitted.w = area;
    if (add(l, (two_sided ? 2.0f : 1.0f) * kPi * area * luminance(e), e))
      index_of_shape[shape] = uint32_t(t.lights.size() - 1);
  };
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    if (t.light_of_triangle[i] != LIGHT_NONE || (g.added && i >= g.first_triangle)) continue;
    const Triangle& tri = scene.triangles[i];
    const glm::vec3 a = to_vec3(tri.v0), b = to_vec3(tri.v1), c = to_vec3(tri.v2);
    add_shape(tri.material, LIGHT_TRIANGLE, tri.v0, tri.v1, tri.v2, 0.5f * glm::length(glm::cross(b - a, c - a)),
              t.light_of_triangle, i);
  }
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    if (t.light_of_sphere[i] != LIGHT_NONE || (g.added && i >= g.first_sphere)) continue;
    const float r = scene.spheres[i].center_radius.w;
    add_shape(scene.spheres[i].material, LIGHT_SPHERE, scene.spheres[i].center_radius, {}, {}, 4.0f * kPi * r * r,
              t.light_of_sphere, i);
  }
  for (size_t i = 0; i < scene.cylinders.size(); ++i) {
    const Cylinder& c = scene.cylinders[i];
    const float r = c.center_radius.w, h = c.axis_half.w;
    add_shape(c.material, LIGHT_CYLINDER, c.center_radius, c.axis_half, {}, 4.0f * kPi * r * h + 2.0f * kPi * r * r,
              t.light_of_cylinder, i);
  }
  set_selection(t.lights, power);
  return t;
}

void set_selection(std::vector<PathLight>& lights, const std::vector<float>& power) {
  double total = 0.0;
  for (float p : power) total += p;
  double prefix = 0.0;
  for (size_t i = 0; i < lights.size(); ++i) {
    lights[i].select_probability = float(power[i] / total);
    prefix += power[i] / total;
    lights[i].select_cdf = i + 1 == lights.size() ? 1.0f : float(prefix);
  }
}

std::vector<PathLight> point_path_lights(const std::vector<PointLight>& points) {
  std::vector<PathLight> lights;
  std::vector<float> power;
  for (const PointLight& p : points) {
    const glm::vec3 i = to_vec3(p.intensity);
    if (!(luminance(i) > 0.0f)) continue;
    PathLight l{};
    l.kind = LIGHT_POINT;
    l.p0 = p.position;
    l.emitted = to_float4(i);
    lights.push_back(l);
    power.push_back(4.0f * kPi * luminance(i));
  }
  set_selection(lights, power);
  return lights;
}

}  // namespace caustica
