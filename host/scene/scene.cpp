#include "host/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/packing.hpp>

#include "host/error.h"
#include "host/limits.h"
#include "host/math_constants.h"

namespace caustica {

namespace {

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

bool degenerate_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 e1 = glm::dvec3(b) - glm::dvec3(a), e2 = glm::dvec3(c) - glm::dvec3(a);
  const double scale = std::max(glm::dot(e1, e1), glm::dot(e2, e2));
  return !(glm::length(glm::cross(e1, e2)) > 1e-7 * scale);  // NaN compares false: degenerate
}

std::vector<std::string> drop_degenerate_shapes(Scene& scene) {
  std::vector<std::string> messages;
  size_t dropped = 0;
  auto note = [&](const std::string& what) {
    if (++dropped <= 8) messages.push_back(what + "; dropped");
  };
  auto positive = [](float v) { return v > 0.0f && std::isfinite(v); };
  std::vector<Sphere> spheres;
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    const Sphere& s = scene.spheres[i];
    if (finite3(to_vec3(s.center_radius)) && positive(s.center_radius.w)) spheres.push_back(s);
    else note("sphere " + std::to_string(i) + " has a zero or non-finite centre or radius");
  }
  std::vector<Cylinder> cylinders;
  for (size_t i = 0; i < scene.cylinders.size(); ++i) {
    const Cylinder& c = scene.cylinders[i];
    const glm::vec3 axis = to_vec3(c.axis_half);
    if (finite3(to_vec3(c.center_radius)) && positive(c.center_radius.w) && positive(c.axis_half.w) &&
        finite3(axis) && glm::length(axis) > 0.5f)  // a unit axis, as the loader writes it
      cylinders.push_back(c);
    else
      note("cylinder " + std::to_string(i) + " has a zero or non-finite radius, height or axis");
  }
  std::vector<Triangle> triangles;
  std::vector<TriangleShading> shading;
  std::vector<TriangleTangents> tangents;
  std::vector<TriangleColours> colours;
  const bool shaded = scene.triangle_shading.size() == scene.triangles.size() && !scene.triangles.empty();
  const bool tangent = scene.triangle_tangents.size() == scene.triangles.size() && !scene.triangles.empty();
  const bool coloured = scene.triangle_colours.size() == scene.triangles.size() && !scene.triangles.empty();
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    if (degenerate_triangle(to_vec3(t.v0), to_vec3(t.v1), to_vec3(t.v2))) {
      note("triangle " + std::to_string(i) + " has zero area or a non-finite vertex");
      continue;
    }
    triangles.push_back(t);
    if (shaded) shading.push_back(scene.triangle_shading[i]);
    if (tangent) tangents.push_back(scene.triangle_tangents[i]);
    if (coloured) colours.push_back(scene.triangle_colours[i]);
  }
  if (dropped == 0) return messages;
  if (dropped > 8) messages.push_back("and " + std::to_string(dropped - 8) + " more degenerate shapes dropped");
  scene.spheres = std::move(spheres);
  scene.cylinders = std::move(cylinders);
  scene.triangles = std::move(triangles);
  if (shaded) scene.triangle_shading = std::move(shading);
  if (tangent) scene.triangle_tangents = std::move(tangents);
  if (coloured) scene.triangle_colours = std::move(colours);
  return messages;
}

TriangleColours vertex_colours(const glm::vec4* rgba) {
  TriangleColours c{};
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 4; ++i) c.rgba[4 * k + i] = glm::packHalf1x16(rgba ? rgba[k][i] : 1.0f);
  return c;
}

Material blank_material() {
  Material m{};
  m.ior = 1.0f;
  m.texture = m.roughness_texture = m.emission_texture = m.normal_texture = -1;
  m.clearcoat_texture = m.clearcoat_roughness_texture = m.clearcoat_normal_texture = -1;
  m.normal_scale = m.clearcoat_normal_scale = m.alpha_factor = 1.0f;
  m.roughness = -1.0f;
  return m;
}

CameraBasis camera_basis(const CameraDesc& camera) {
  if (!finite3(camera.position) || !finite3(camera.look_at) || !finite3(camera.up))
    throw Error("degenerate camera: position, lookAt and upVector must be finite");
  // Differences are taken in double so that huge but distinct coordinates do
  // not collapse to a zero view direction.
  const glm::dvec3 f = glm::dvec3(camera.look_at) - glm::dvec3(camera.position);
  const double f_len = glm::length(f);
  if (!(f_len > 0.0) || !std::isfinite(f_len))
    throw Error("degenerate camera: lookAt equals position, so there is no view direction");
  const glm::dvec3 up(camera.up);
  const double up_len = glm::length(up);
  if (!(up_len > 0.0)) throw Error("degenerate camera: upVector is the zero vector");
  const glm::dvec3 forward = f / f_len;
  const glm::dvec3 r = glm::cross(up / up_len, forward);
  // |r| = sin(angle between up and forward): below ~1e-6 the basis is noise.
  const double r_len = glm::length(r);
  if (!(r_len > 1e-6)) throw Error("degenerate camera: upVector is parallel to the view direction (lookAt - position)");
  const glm::dvec3 right = r / r_len;
  const glm::dvec3 true_up = glm::cross(forward, right);
  return CameraBasis{glm::vec3(forward), glm::vec3(right), glm::vec3(true_up)};
}

bool within_coordinate_limit(const glm::dvec3& p) {
  for (int i = 0; i < 3; ++i)
    if (!(std::fabs(p[i]) <= double(limits::kMaxSceneCoordinate))) return false;
  return true;
}

std::string beyond_coordinate_limit(const glm::dvec3& p) {
  char text[160];
  std::snprintf(text, sizeof text, "at (%.4g, %.4g, %.4g), beyond +-1e12 scene units", p.x, p.y, p.z);
  return std::string(text) +
         " (the coordinate limit: distances squared and cubed must fit a float; scale the scene down)";
}

CameraGPU camera_for_image(const CameraDesc& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw Error("camera: image size must be positive");
  const CameraBasis basis = camera_basis(camera);
  const float tan_half = std::tan(camera.fov_y_degrees * 0.5f * kPiF / 180.0f);
  const float aspect = float(width) / float(height);
  CameraGPU cam{};
  cam.position = to_float4(camera.position);
  cam.forward = to_float4(basis.forward);
  cam.right = to_float4(basis.right * (tan_half * aspect));
  cam.up = to_float4(basis.up * tan_half);
  cam.lens = cs_float4{camera.aperture_radius, camera.focus_distance, 0.0f, 0.0f};
  cam.width = cs_uint(width);
  cam.height = cs_uint(height);
  cam.pixel_offset = 0;
  cam.pixel_count = cs_uint(size_t(width) * size_t(height));
  return cam;
}

const char* render_mode_name(RenderMode mode) {
  static const char* const names[] = {"binary", "phong", "path"};  // in RenderMode's order
  return names[static_cast<int>(mode)];
}

}  // namespace caustica
