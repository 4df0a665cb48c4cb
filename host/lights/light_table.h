// The lights each integrator uploads, derived from the scene's one form
// (Scene::lights, Light in kernels/shared/types.h) through the light types
// (host/lights/light_types.h).
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Appends the geometry of every light whose type has some (rectangle and
// sphere lights), with an emissive material that reflects nothing, so that
// BSDF-sampled rays hit the lights they could have sampled (MIS needs both
// ways to reach a light). Path mode only; before the BVH is built.
void add_light_geometry(Scene& scene);

struct LightTable {
  std::vector<Light> lights;                // selection probability by power
  std::vector<uint32_t> light_of_sphere;    // per sphere: its light, or LIGHT_NONE
  std::vector<uint32_t> light_of_cylinder;  // per cylinder
  std::vector<uint32_t> light_of_triangle;  // per triangle: its light, or LIGHT_NONE
  uint32_t environment = LIGHT_NONE;        // the environment's index (last), if the scene has one that emits
  std::vector<float> power;                 // per light: the weight it is picked by (the light tree's power)
};

// The path tracer's lights: the file's (their geometry added first), then
// every other emissive triangle (front side, or both with "twosided"),
// sphere and cylinder (outward). File lights come by kind (the registry's
// order), then as the file lists them; the environment last.
LightTable build_light_table(const Scene& scene);

// Phong's lights: each file light's delta stand-in (point and spot lights
// themselves, a point at the centre of a rectangle or sphere light), by
// kind.
std::vector<Light> whitted_lights(const Scene& scene);

// The lights of `lights` that emit, with selection probabilities by power.
std::vector<Light> emitting_lights(const std::vector<Light>& lights);

// Phong's photon lights (--caustics on): its delta stand-ins that emit,
// then the environment (the path tracer's entry, environment_light: the
// same power and bounding sphere), picked by power. The stand-ins' power is
// in phong's units (no distance falloff) and the sky's is flux: the mix
// only sets how many photons each gets, not what they carry.
std::vector<Light> phong_photon_lights(const Scene& scene);

// select_probability and select_cdf of `lights` from their powers.
void set_selection(std::vector<Light>& lights, const std::vector<float>& power);

}  // namespace caustica
