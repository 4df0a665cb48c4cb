// What a scene needs, decided once on the host. Two tiers (DESIGN.md):
// run time (stages and buffers not launched/allocated) and compile time (a
// few coarse -D flags, the HAS_* of kernels/shared/feature_flags.h). Keep
// the flags coarse: each distinct feature set is one program build and one
// cache entry, so a flag must cut a whole code path, never encode a
// per-scene number.
#pragma once

#include <string>

#include "host/scene/scene.h"
#include "kernels/shared/feature_flags.h"

namespace caustica {

// --caustics: the photon pass (path mode) when the scene has casters
// (auto), always, or never.
enum class CausticsMode { Auto, On, Off };
CausticsMode parse_caustics_mode(const std::string& name);  // auto | on | off

// Does the path tracer treat this material as a caustic caster (smooth or
// glossy metal and glass) anywhere on its surface? bsdf_casts_caustics(
// bsdf_of_material(m)), the kernels' own functions (kernels/lib/material.h)
// compiled for the host. A material with a roughness_texture (glTF
// metallicRoughnessTexture) is judged at its smoothest, most metallic texel
// values (conservative: it casts if any texel might), and receives if its
// roughest, least metallic values do not cast; it can do both.
bool material_casts_caustics(const Scene& scene, const Material& m);
bool material_receives_caustics(const Scene& scene, const Material& m);

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
  bool normal_maps = false;       // a used material's normal map, on triangles with tangents
  bool vertex_colours = false;    // triangles' vertex colours (glTF COLOR_0)
  bool clearcoat = false;         // a used material's clear coat (path mode, photon pass)
  bool alpha_cutouts = false;     // a used triangle material with alpha MASK or BLEND (every mode: rays see it)
  bool caustics = false;  // path: the photon pass (kernels compiled, buffers allocated, stages launched)
  std::string caustics_reason;  // why it is or is not there, for --verbose
  bool check_numerics = false;  // path: --check-numerics counters compiled in (set by the session)
  bool aux_passes = false;      // path: the albedo, normal and depth passes compiled in (set by the session)
  bool environment = false;     // path and phong: the scene's environment map (seen at misses; path: sampled)
  bool light_tree = false;      // path: NEE picks lights through the light tree (set by the session: --light-sampler)
  bool secondary_rays() const { return reflection || refraction; }

  // The value (0 or 1) this scene gives a feature flag.
  int flag_value(FeatureFlag flag) const;
  std::string build_options() const;  // every flag, " -DHAS_X=v" in table order
  std::string describe() const;       // one line for --verbose: mode, then each flag's word=yes|no
};

SceneFeatures analyse_scene(const Scene& scene, RenderMode mode, CausticsMode caustics = CausticsMode::Auto);

}  // namespace caustica
