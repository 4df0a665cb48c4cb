#include "host/render/device_scene.h"

namespace caustica {

DeviceScene::DeviceScene(cl::Context& context, const Scene& scene, const WideBvh& bvh, const SceneFeatures& features)
    : scene_(scene), features_(features) {
  size_t* total = &uploaded_bytes_;
  nodes_ = upload_buffer(context, bvh.nodes, total);
  triangle_blocks_ = upload_buffer(context, bvh.triangle_blocks, total);
  prim_refs_ = upload_buffer(context, bvh.prim_refs, total);
  spheres_ = upload_buffer(context, scene.spheres, total);
  cylinders_ = upload_buffer(context, scene.cylinders, total);
  triangles_ = upload_buffer(context, scene.triangles, total);
  static const std::vector<TriangleShading> no_shading;
  static const std::vector<Texture> no_textures;
  static const std::vector<uint16_t> no_texels;
  static const std::vector<Material> no_materials;
  triangle_shading_ = upload_buffer(context, features.triangle_shading ? scene.triangle_shading : no_shading, total);
  materials_ = upload_buffer(context, features.materials ? scene.materials : no_materials, total);
  textures_ = upload_buffer(context, features.textures ? scene.textures : no_textures, total);
  texels_ = upload_buffer(context, features.textures ? scene.texels : no_texels, total);
}

KernelArgs& DeviceScene::bind_geometry(KernelArgs& args) const {
  return args.arg("bvh_nodes", nodes_)
      .arg("tri_blocks", triangle_blocks_)
      .arg("prim_refs", prim_refs_)
      .arg("spheres", spheres_)
      .arg("cylinders", cylinders_)
      .arg("triangles", triangles_);
}

KernelArgs& DeviceScene::bind_surfaces(KernelArgs& args) const {
  return args.arg("spheres", spheres_)
      .arg("cylinders", cylinders_)
      .arg("triangles", triangles_)
      .arg("triangle_shading", triangle_shading_)
      .arg("materials", materials_)
      .arg("textures", textures_)
      .arg("texels", texels_);
}

}  // namespace caustica
