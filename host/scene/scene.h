// The in-memory scene: what the loader produces and everything downstream
// (feature analysis, BVH build, upload) consumes. Geometry, materials and
// lights are stored directly in their device layout (kernels/shared/types.h)
// so that upload is a copy, not a conversion.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "kernels/shared/types.h"

namespace caustica {

enum class RenderMode { Binary, Phong };

struct CameraDesc {
  int width = 0;
  int height = 0;
  glm::vec3 position{0.0f};
  glm::vec3 look_at{0.0f, 0.0f, 1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y_degrees = 45.0f;  // vertical field of view
  float exposure = 0.0f;        // the JSON "exposure", in stops (image scale 2^exposure)
};

struct Scene {
  std::string source_path;  // file the scene came from (for messages)
  RenderMode mode = RenderMode::Phong;
  int nbounces = 4;
  CameraDesc camera;
  glm::vec3 background{0.0f};
  std::vector<PointLight> point_lights;
  std::vector<Material> materials;
  std::vector<Sphere> spheres;
  std::vector<Cylinder> cylinders;
  std::vector<Triangle> triangles;

  size_t primitive_count() const { return spheres.size() + cylinders.size() + triangles.size(); }
};

inline cs_float4 to_float4(const glm::vec3& v, float w = 0.0f) { return cs_float4{v.x, v.y, v.z, w}; }
inline glm::vec3 to_vec3(const cs_float4& v) { return glm::vec3(v.x, v.y, v.z); }

// Camera basis per the coursework convention: right = up x forward, so with
// forward +z and up +y, world +x is on the image's right.
struct CameraBasis {
  glm::vec3 forward, right, up;
};
CameraBasis camera_basis(const CameraDesc& camera);

}  // namespace caustica
