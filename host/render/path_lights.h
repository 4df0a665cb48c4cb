// The scene's lights as the path tracer samples them (PathLight,
// kernels/shared/types.h; kernels/lib/path_lights.h samples them).
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Appends the geometry of every rectangle light (two triangles) and sphere
// light (a sphere), with an emissive material that reflects nothing, so that
// BSDF-sampled rays hit the lights they could have sampled (MIS needs both
// ways to reach a light). Path mode only; before the BVH is built.
void add_light_geometry(Scene& scene);

struct PathLightTable {
  std::vector<PathLight> lights;            // selection probability by power
  std::vector<uint32_t> light_of_sphere;    // per sphere: its light, or LIGHT_NONE
  std::vector<uint32_t> light_of_cylinder;  // per cylinder
  std::vector<uint32_t> light_of_triangle;  // per triangle: its light, or LIGHT_NONE
  float max_radiance = 0.0f;                // largest emitted component, tiny lights scaled down (film scale)
};

// Point lights; rectangle and sphere lights (their geometry added first);
// every other emissive triangle (front side, or both with "twosided"),
// sphere and cylinder (outward).
PathLightTable build_path_lights(const Scene& scene);

// Point lights as path lights (phong's photon pass emits from its point
// lights and stand-ins), picked in proportion to power.
std::vector<PathLight> point_path_lights(const std::vector<PointLight>& points);
// select_probability and select_cdf of `lights` from their powers.
void set_selection(std::vector<PathLight>& lights, const std::vector<float>& power);

}  // namespace caustica
