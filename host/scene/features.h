// What a scene needs, decided once on the host. Two tiers (DESIGN.md):
// run time (stages and buffers not launched/allocated) and compile time (a
// few coarse -D flags). Keep the flags coarse: each distinct feature set is
// one program build and one cache entry, so a flag must cut a whole code
// path, never encode a per-scene number.
#pragma once

#include <string>

#include "host/scene/scene.h"

namespace caustica {

struct SceneFeatures {
  RenderMode mode = RenderMode::Phong;
  bool spheres = false;
  bool cylinders = false;
  bool triangles = false;
  bool materials = false;   // shading reads materials (not binary)
  bool lights = false;      // phong: shadow stage runs
  bool reflection = false;  // phong: mirror rays spawned
  bool refraction = false;  // phong: dielectric rays spawned
  bool textures = false;    // some used material has a texture
  bool area_lights = false; // path: rectangle, sphere or emissive-shape lights are sampled
  bool triangle_shading = false;  // vertex normals / texture coordinates on triangles
  bool secondary_rays() const { return reflection || refraction; }

  std::string build_options() const;  // the -D flags
  std::string describe() const;       // one line for --verbose
};

SceneFeatures analyse_scene(const Scene& scene, RenderMode mode);

}  // namespace caustica
