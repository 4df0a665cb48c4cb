// A glTF file as a whole scene (`caustica render model.glb`): its triangles
// and materials, the camera LoadOptions::gltf_camera picks, its punctual
// lights, and the documented stand-ins (scenes/FORMAT.md, "glTF 2.0 files")
// where it has no camera or no light. caustica's camera has right = up x
// forward (the coursework convention) where glTF's is right-handed, so the
// file is loaded mirrored in x (the root transform diag(-1, 1, 1)): images
// look as in any glTF viewer.
#include <cmath>
#include <filesystem>
#include <iostream>

#include "host/error.h"
#include "host/lights/light_types.h"
#include "host/math_constants.h"
#include "host/scene/gltf.h"
#include "host/scene/scene_reader.h"

namespace caustica {

namespace {

using namespace scene_detail;

constexpr int kDefaultLongSide = 800;       // pixels, when the file's camera gives only an aspect
constexpr float kDefaultAspect = 4.0f / 3.0f;

void size_image(CameraDesc& c, float aspect) {
  if (!(aspect > 0.0f)) aspect = kDefaultAspect;
  c.width = aspect >= 1.0f ? kDefaultLongSide : std::max(1, int(std::lround(kDefaultLongSide * aspect)));
  c.height = aspect >= 1.0f ? std::max(1, int(std::lround(kDefaultLongSide / aspect))) : kDefaultLongSide;
}

CameraDesc pick_camera(const Reader& r, const GltfModel& model, const LoadOptions& options) {
  const GltfCamera* chosen = nullptr;
  if (options.gltf_camera) {
    const int n = *options.gltf_camera;
    if (n < 0 || static_cast<size_t>(n) >= model.camera_count)
      throw Error("--camera " + std::to_string(n) + ": " + r.file() + " has " + std::to_string(model.camera_count) +
                  (model.camera_count == 1 ? " camera" : " cameras") +
                  (model.camera_count ? " (0 to " + std::to_string(model.camera_count - 1) + ")" : ""));
    for (const GltfCamera& c : model.cameras)
      if (c.index == n) chosen = chosen ? chosen : &c;
    if (!chosen)
      throw Error("--camera " + std::to_string(n) + ": " + r.file() + ": /cameras/" + std::to_string(n) +
                  " is not placed by any node of the scene (or is not a perspective camera)");
  } else {
    for (const GltfCamera& c : model.cameras)
      if (!chosen || c.index < chosen->index) chosen = &c;
  }
  if (!chosen) {
    r.warn("/cameras", "no camera; using the default view of the whole scene (FORMAT.md, \"glTF 2.0 files\")");
    return gltf_default_camera(model.lo, model.hi);
  }
  CameraDesc c;
  c.position = chosen->position;
  c.look_at = chosen->position + chosen->forward;
  c.up = chosen->up;
  c.fov_y_degrees = static_cast<float>(chosen->yfov_radians * 180.0 / kPi);
  c.focus_distance = 1.0f;
  size_image(c, chosen->aspect);
  try {
    camera_basis(c);
  } catch (const Error& e) {
    r.fail("/cameras/" + std::to_string(chosen->index), e.what());
  }
  return c;
}

void add_lights(const Reader& r, const GltfModel& model, Scene& scene) {
  for (const GltfLight& l : model.lights) {
    if (l.type == GltfLight::Type::Point) {
      scene.lights.push_back(delta_light_at(l.position, l.intensity));
    } else if (l.type == GltfLight::Type::Spot) {
      double outer = l.outer_cone * 180.0 / kPi, inner = l.inner_cone * 180.0 / kPi;
      if (!(outer > 0.0 && outer <= 90.0) || !(inner >= 0.0 && inner < outer))
        r.fail(l.pointer + "/spot", "expected 0 <= innerConeAngle < outerConeAngle <= pi/2, got " +
                                        std::to_string(l.inner_cone) + " and " + std::to_string(l.outer_cone));
      if (outer < 0.5) {  // the kernels' narrowest cone (spot_light.cpp)
        r.warn(l.pointer + "/spot/outerConeAngle", "cones narrower than 0.5 degrees are widened to 0.5");
        inner = inner * 0.5 / outer;
        outer = 0.5;
      }
      scene.lights.push_back(spot_light_at(l.position, l.direction, l.intensity, inner, outer));
    } else {
      // Along the node's -z (GltfLight::direction); lux read as W/m^2.
      scene.lights.push_back(directional_light_along(l.direction, l.intensity));
    }
    scene.light_sources.resize(scene.lights.size(), l.pointer);
  }
}

}  // namespace

Material gltf_default_material() {
  Material m = default_material();
  m.diffuse = to_float4(glm::vec3(1.0f), 1.0f);
  m.specular = to_float4(glm::vec3(1.0f), 0.04f);
  m.metallic = 1.0f;
  m.roughness = 1.0f;
  m.specular_exponent = 0.0f;
  return m;
}

CameraDesc gltf_default_camera(const glm::vec3& lo, const glm::vec3& hi) {
  const float fov = 45.0f;
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  const float distance = radius / std::sin(0.5f * fov * float(kPi) / 180.0f);
  CameraDesc c;
  c.position = centre + glm::vec3(0.0f, 0.0f, distance);
  c.look_at = centre;
  c.up = glm::vec3(0.0f, 1.0f, 0.0f);
  c.fov_y_degrees = fov;
  c.focus_distance = distance;
  size_image(c, kDefaultAspect);
  return c;
}

Scene load_gltf_scene(const std::string& path, const LoadOptions& options) {
  const Reader r(path, options);
  Scene scene;
  scene.source_path = path;
  scene.mode = RenderMode::Path;
  scene.nbounces = 8;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  LoadContext ctx(r, scene, dir.empty() ? std::string(".") : dir.string(), std::filesystem::path(path).stem().string());
  const glm::dmat4 mirror_x = glm::dmat4(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0),
                                         glm::dvec4(0, 0, 0, 1));
  const GltfModel model = import_gltf(path, ctx.textures, mirror_x);
  for (const std::string& w : model.warnings) r.forward_warning(w);
  if (model.mesh.triangles.empty())
    r.warn("/scenes", "the file's scene places no triangles (" + std::to_string(model.mesh.dropped_degenerate) +
                          " degenerate ones dropped); the image shows only the background");
  if (model.mesh.dropped_degenerate > 0)
    r.warn("/meshes", std::to_string(model.mesh.dropped_degenerate) + " zero-area triangles dropped");
  std::vector<cs_uint> ids(model.materials.size() + 1);
  ids[0] = ctx.materials.add(gltf_default_material());
  for (size_t i = 0; i < model.materials.size(); ++i) ids[i + 1] = ctx.materials.add(model.materials[i]);
  bool emissive = false;
  for (const MeshTriangle& t : model.mesh.triangles) {
    const cs_uint m = ids[size_t(t.material + 1)];
    emissive = emissive || glm::any(glm::greaterThan(to_vec3(scene.materials[m].emission), glm::vec3(0.0f)));
    append_triangle(ctx, t.p, m, t.has_uvs ? t.uv : nullptr, t.has_normals ? t.n : nullptr,
                    t.has_tangents ? t.tangent : nullptr, t.has_colours ? t.colour : nullptr);
  }
  finish_shading(ctx);
  scene.camera = pick_camera(r, model, options);
  add_lights(r, model, scene);
  if (scene.lights.empty() && !emissive) {
    scene.background = glm::vec3(1.0f);
    r.warn("/extensions/KHR_lights_punctual", "no lights and no emissive materials; lit by a uniform white sky "
                                              "(background 1, FORMAT.md)");
  }
  Scene::MeshInfo info;
  info.file = path;
  info.triangles = scene.triangles.size();
  info.dropped_degenerate = model.mesh.dropped_degenerate;
  scene.meshes.push_back(info);
  r.flush_deferred();
  return scene;
}

}  // namespace caustica
