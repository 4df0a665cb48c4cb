#include "host/render/device_lights.h"

#include "host/render/device_scene.h"

namespace caustica {

DeviceLights::DeviceLights(cl::Context& context, const LightTable& table, const LightTree& tree)
    : count_(table.lights.size()),
      lights_(upload_buffer(context, table.lights)),
      light_of_sphere_(upload_buffer(context, table.light_of_sphere)),
      light_of_cylinder_(upload_buffer(context, table.light_of_cylinder)),
      light_of_triangle_(upload_buffer(context, table.light_of_triangle)) {
  upload_tree(context, tree);
}

void DeviceLights::upload_tree(cl::Context& context, const LightTree& tree) {
  light_tree_nodes_ = upload_buffer(context, tree.nodes.empty() ? std::vector<LightTreeNode>(1) : tree.nodes);
  light_tree_trails_ = upload_buffer(context, tree.trails.empty() ? std::vector<LightTreeTrail>(1) : tree.trails);
}

DeviceLights::DeviceLights(cl::Context& context, const std::vector<Light>& lights)
    : count_(lights.size()), lights_(upload_buffer(context, lights)) {
  const std::vector<uint32_t> none{LIGHT_NONE};
  light_of_sphere_ = upload_buffer(context, none);
  light_of_cylinder_ = upload_buffer(context, none);
  light_of_triangle_ = upload_buffer(context, none);
  upload_tree(context, LightTree{});
}

KernelArgs& DeviceLights::bind(KernelArgs& args) const {
  return args.arg("lights", lights_)
      .arg("light_of_sphere", light_of_sphere_)
      .arg("light_of_cylinder", light_of_cylinder_)
      .arg("light_of_triangle", light_of_triangle_)
      .arg("light_tree_nodes", light_tree_nodes_)
      .arg("light_tree_trails", light_tree_trails_);
}

}  // namespace caustica
