// Photons a light emits, through its type's emission code compiled for the
// host (kernels/lib/lights.h through kernels/shared/compat.h): n photons
// from uniform random numbers of `seed`, each handed to
// visit(origin, direction, flux). The light types' power tests share it.
#pragma once

#include <cstdint>
#include <random>

#include "host/lights/light_types.h"

namespace caustica::test {

// `data`: the environment buffer for an environment light, else nullptr.
template <class Visit>
void emit_photons(const Light& light, const float* data, int n, uint32_t seed, Visit visit) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < n; ++i) {
    float3 p_error, normal, origin, dir;
    const float3 point = light_emission_point(&light, data, make_float2(u01(rng), u01(rng)), &p_error, &normal);
    const float3 flux = light_emit(&light, data, point, p_error, normal, make_float2(u01(rng), u01(rng)), u01(rng),
                                   &origin, &dir);
    visit(origin, dir, flux);
  }
}

}  // namespace caustica::test
