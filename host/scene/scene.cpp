#include "host/scene/scene.h"

#include <cmath>

#include "host/error.h"

namespace caustica {

namespace {

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

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

CameraGPU camera_for_image(const CameraDesc& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw Error("camera: image size must be positive");
  const CameraBasis basis = camera_basis(camera);
  const float tan_half = std::tan(camera.fov_y_degrees * 0.5f * 3.14159265358979f / 180.0f);
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
