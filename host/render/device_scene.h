// The scene on the device: geometry, the wide BVH, shading data (triangle
// vertex data, materials, textures), uploaded once and shared by every
// integrator, every pass and the benchmark. Lights are not here: each
// integrator uploads the lights in the form it samples (DeviceLights for the
// path tracer and the photon pass; Whitted's point lights are stand-ins
// derived from the scene's lights, host/render/lights.h).
// Data the feature set leaves out is not uploaded (a one-element dummy:
// OpenCL forbids zero-sized buffers).
#pragma once

#include <CL/opencl.hpp>

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "host/accel/bvh_wide.h"
#include "host/render/device_lights.h"
#include "host/render/kernel_args.h"
#include "host/scene/features.h"
#include "host/scene/scene.h"

namespace caustica {

class DeviceScene {
 public:
  DeviceScene(cl::Context& context, const Scene& scene, const WideBvh& bvh, const SceneFeatures& features);

  // SCENE_GEOMETRY_PARAMS (kernels/lib/geometry.h), in order.
  KernelArgs& bind_geometry(KernelArgs& args) const;
  // SCENE_SURFACE_PARAMS (kernels/lib/surface.h), in order.
  KernelArgs& bind_surfaces(KernelArgs& args) const;
  // Both: the BVH's own buffers, then bind_surfaces (trace_paths.cl traces
  // and shades in one kernel).
  KernelArgs& bind_scene(KernelArgs& args) const;
  // SCENE_BUFFERS_PARAMS (kernels/lib/scene_buffers.h): bind_scene, then
  // the light table's buffers.
  KernelArgs& bind_scene_buffers(KernelArgs& args, const DeviceLights& lights) const;

  const Scene& scene() const { return scene_; }
  const SceneFeatures& features() const { return features_; }
  size_t uploaded_bytes() const { return uploaded_bytes_; }

 private:
  KernelArgs& bind(KernelArgs& args, std::initializer_list<const char*> names) const;

  const Scene& scene_;
  SceneFeatures features_;
  size_t uploaded_bytes_ = 0;
  std::vector<std::pair<std::string, cl::Buffer>> buffers_;
};

// A read-only buffer holding `data` (one dummy element when it is empty).
template <typename T, typename Allocator>
cl::Buffer upload_buffer(cl::Context& context, const std::vector<T, Allocator>& data, size_t* bytes_total = nullptr) {
  const size_t bytes = std::max<size_t>(1, data.size()) * sizeof(T);
  if (bytes_total) *bytes_total += bytes;
  if (data.empty()) return cl::Buffer(context, CL_MEM_READ_ONLY, bytes);
  return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<T*>(data.data()));
}

}  // namespace caustica
