#include "host/render/device_lights.h"

#include "host/render/device_scene.h"

namespace caustica {

DeviceLights::DeviceLights(cl::Context& context, const LightTable& table)
    : count_(table.lights.size()),
      lights_(upload_buffer(context, table.lights)),
      light_of_sphere_(upload_buffer(context, table.light_of_sphere)),
      light_of_cylinder_(upload_buffer(context, table.light_of_cylinder)),
      light_of_triangle_(upload_buffer(context, table.light_of_triangle)) {}

DeviceLights::DeviceLights(cl::Context& context, const std::vector<Light>& lights)
    : count_(lights.size()), lights_(upload_buffer(context, lights)) {
  const std::vector<uint32_t> none{LIGHT_NONE};
  light_of_sphere_ = upload_buffer(context, none);
  light_of_cylinder_ = upload_buffer(context, none);
  light_of_triangle_ = upload_buffer(context, none);
}

KernelArgs& DeviceLights::bind(KernelArgs& args) const {
  return args.arg("lights", lights_)
      .arg("light_of_sphere", light_of_sphere_)
      .arg("light_of_cylinder", light_of_cylinder_)
      .arg("light_of_triangle", light_of_triangle_);
}

}  // namespace caustica
