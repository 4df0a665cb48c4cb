#include "host/render/lights.h"

namespace caustica {

std::vector<PointLight> whitted_point_lights(const Scene& scene) {
  std::vector<PointLight> lights;
  auto add = [&](const glm::vec3& position, const glm::vec3& intensity) {
    PointLight p{};
    p.position = to_float4(position);
    p.intensity = to_float4(intensity);
    lights.push_back(p);
  };
  for (const PointLightDesc& l : scene.point_lights) add(l.position, l.intensity);
  for (const AreaLightDesc& l : scene.area_lights) add(l.center, l.intensity);
  for (const SphereLightDesc& l : scene.sphere_lights) add(l.center, l.intensity);
  return lights;
}

}  // namespace caustica
