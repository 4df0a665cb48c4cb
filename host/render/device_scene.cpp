#include "host/render/device_scene.h"

#include <algorithm>

#include "host/lights/environment_light.h"
#include "host/scene/alpha_cutouts.h"

namespace caustica {

DeviceScene::DeviceScene(cl::Context& context, const Scene& scene, const WideBvh& bvh, const SceneFeatures& features)
    : scene_(scene), features_(features) {
  // Named as the kernels' parameters (SCENE_GEOMETRY_PARAMS, SCENE_SURFACE_PARAMS).
  auto add = [&](const char* name, const auto& data) {
    buffers_.emplace_back(name, upload_buffer(context, data, &uploaded_bytes_));
  };
  add("bvh_nodes", bvh.nodes);
  add("tri_blocks", bvh.triangle_blocks);
  add("prim_refs", bvh.prim_refs);
  add("spheres", scene.spheres);
  add("cylinders", scene.cylinders);
  add("triangles", scene.triangles);
  static const std::vector<TriangleShading> no_shading;
  static const std::vector<Texture> no_textures;
  static const std::vector<uint16_t> no_texels;
  static const std::vector<Material> no_materials;
  add("triangle_shading", features.triangle_shading ? scene.triangle_shading : no_shading);
  static const std::vector<TriangleTangents> no_tangents;
  static const std::vector<TriangleColours> no_colours;
  add("triangle_tangents", features.normal_maps ? scene.triangle_tangents : no_tangents);
  add("triangle_colours", features.vertex_colours ? scene.triangle_colours : no_colours);
  add("materials", features.materials ? scene.materials : no_materials);
  add("textures", features.textures ? scene.textures : no_textures);
  add("texels", features.textures ? scene.texels : no_texels);
  // The traversal's cut-outs read the same texels under their own name.
  const cl::Buffer texels = buffers_.back().second;
  buffers_.emplace_back("alpha_texels", texels);
  static const std::vector<TriangleAlpha> no_alpha;
  add("triangle_alpha", features.alpha_cutouts ? triangle_alpha(scene) : no_alpha);
  static const std::vector<float> no_environment;
  add("environment", features.environment ? environment_device_data(scene) : no_environment);
}

KernelArgs& DeviceScene::bind(KernelArgs& args, std::initializer_list<const char*> names) const {
  for (const char* name : names) {
    const auto it = std::find_if(buffers_.begin(), buffers_.end(), [&](const auto& b) { return b.first == name; });
    args.arg(name, it->second);
  }
  return args;
}

KernelArgs& DeviceScene::bind_geometry(KernelArgs& args) const {
  return bind(args,
              {"bvh_nodes", "tri_blocks", "prim_refs", "spheres", "cylinders", "triangles", "triangle_alpha", "alpha_texels"});
}

KernelArgs& DeviceScene::bind_surfaces(KernelArgs& args) const {
  return bind(args,
              {"spheres", "cylinders", "triangles", "triangle_shading", "triangle_tangents", "triangle_colours",
               "materials", "textures", "texels", "environment"});
}

KernelArgs& DeviceScene::bind_scene(KernelArgs& args) const {
  return bind_surfaces(bind(args, {"bvh_nodes", "tri_blocks", "prim_refs", "triangle_alpha", "alpha_texels"}));
}

KernelArgs& DeviceScene::bind_scene_buffers(KernelArgs& args, const DeviceLights& lights) const {
  return lights.bind(bind_scene(args));
}


}  // namespace caustica
