// A light table on the device, in the form the path tracer and the photon
// pass sample it (LightTable, host/lights/light_table.h): the lights and,
// per primitive, the light it is (what a BSDF-sampled ray that hits it
// weighs by MIS). Named as the light parameters of SCENE_BUFFERS_PARAMS
// (kernels/lib/scene_buffers.h), which DeviceScene::bind_scene_buffers
// binds after the scene's own buffers: every stage that takes the scene
// as one struct is bound by that one call.
#pragma once

#include <CL/opencl.hpp>

#include <vector>

#include "host/lights/light_table.h"
#include "host/lights/light_tree.h"
#include "host/render/kernel_args.h"

namespace caustica {

class DeviceLights {
 public:
  DeviceLights() = default;
  // The path tracer's table, and the tree next-event estimation walks
  // (empty: the power CDF; the program is built without HAS_LIGHT_TREE).
  DeviceLights(cl::Context& context, const LightTable& table, const LightTree& tree = {});
  // Lights that are no primitive of the scene (phong's photon lights): every
  // primitive maps to LIGHT_NONE (one-element maps: no stage that these
  // programs run reads them).
  DeviceLights(cl::Context& context, const std::vector<Light>& lights);

  // lights, light_of_sphere, light_of_cylinder, light_of_triangle,
  // light_tree_nodes, light_tree_trails, in order (a one-element tree
  // where there is none: no stage of such a program reads it).
  KernelArgs& bind(KernelArgs& args) const;
  const cl::Buffer& lights() const { return lights_; }
  size_t count() const { return count_; }

 private:
  size_t count_ = 0;
  cl::Buffer lights_, light_of_sphere_, light_of_cylinder_, light_of_triangle_;
  cl::Buffer light_tree_nodes_, light_tree_trails_;
  void upload_tree(cl::Context& context, const LightTree& tree);
};

}  // namespace caustica
