// Bench only: traces a host-made ray batch with a ray kernel over the device
// scene, and times it. The kernel takes (SCENE_GEOMETRY_PARAMS,
// RAY_VIEW_PARAMS(rays), T* result) with one result of result_bytes per ray
// (intersect_closest: a Hit named "hits"; kernels/bench/trace_shadow_only.cl:
// a uint named "occluded"), result_name being that parameter's name.
#pragma once

#include <vector>

#include "host/cl/runtime.h"
#include "host/render/device_scene.h"

namespace caustica {

// All rays go in one launch of `local_size`; returns the median of
// `repetitions` launches in ms, after one warm-up launch of the same grid
// (PoCL compiles per launch shape). The last launch's results are copied to
// `results` (size() * result_bytes bytes) when it is not null.
double time_ray_kernel(Runtime& runtime, const DeviceScene& scene, StageKernel& kernel, const char* result_name,
                       const std::vector<cs_float4>& origin, const std::vector<cs_float4>& dir, size_t result_bytes,
                       int repetitions, void* results = nullptr, size_t local_size = 64);

}  // namespace caustica
