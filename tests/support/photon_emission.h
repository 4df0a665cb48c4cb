// Photons a light emits, through its type's emission code compiled for the
// host (kernels/lib/lights.h through kernels/shared/compat.h): n photons
// from uniform random numbers of `seed`, each handed to
// visit(origin, direction, flux). The light types' power tests share it.
// emit_photons_on_device runs the photon pass's own stage instead
// (emit_photons.cl), for what only the device has: the scene's textures.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "host/app/session.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

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

// The photon pass's emit_photons stage, unguided (no casters), in session
// s (built with the photon pass): n photons from `table`'s lights; one
// field of each photon record ("power", "dir", "origin", ...).
inline std::vector<cs_float4> emit_photons_on_device(Session& s, const LightTable& table, uint32_t n,
                                                     const char* field) {
  StageLauncher launcher(*s.runtime, 64);
  const DeviceLights lights(s.runtime->context(), table);
  DeviceQueue out(s.runtime->context(), photon_record_layout(), n);
  StageKernel emit(s.program.program, "emit_photons");
  PhotonPassParams p{};
  p.photon_count = p.photon_end = n;
  p.light_count = cl_uint(table.lights.size());
  const cl::Buffer no_casters(s.runtime->context(), CL_MEM_READ_ONLY, sizeof(cs_float4));
  KernelArgs args(emit);
  s.device_scene->bind_scene_buffers(args, lights)
      .arg("params", p)
      .arg("casters", no_casters)
      .arg("caster_count", cl_uint(0))
      .queue("out", out)
      .arg("next_count", out.count())  // no bounce follows: any counter will do
      .finish();
  launcher.launch(emit, n, nullptr);
  std::vector<cs_float4> values(n);
  s.runtime->queue().enqueueReadBuffer(out.field(field), CL_TRUE, 0, n * sizeof(cs_float4), values.data());
  return values;
}

}  // namespace caustica::test
