#include "host/scene/features.h"

#include <algorithm>
#include <cmath>

#include "host/error.h"
#include "host/lights/light_types.h"
#include "lib/material.h"

namespace caustica {

CausticsMode parse_caustics_mode(const std::string& name) {
  if (name == "auto") return CausticsMode::Auto;
  if (name == "on") return CausticsMode::On;
  if (name == "off") return CausticsMode::Off;
  throw Error("--caustics " + name + ": expected auto, on or off");
}

// The kernels' own material mapping and caster test (kernels/lib/material.h,
// compiled here through kernels/shared/compat.h): the scene analysis and
// the photon pass cannot disagree about which surfaces cast.
bool material_casts_caustics(const Material& m) { return bsdf_casts_caustics(bsdf_of_material(&m, m.diffuse.xyz)); }

SceneFeatures analyse_scene(const Scene& scene, RenderMode mode, CausticsMode caustics) {
  SceneFeatures f;
  f.mode = mode;
  f.spheres = !scene.spheres.empty();
  f.cylinders = !scene.cylinders.empty();
  f.triangles = !scene.triangles.empty();
  if (mode == RenderMode::Binary) return f;  // binary shading needs no lights, materials or textures
  f.materials = true;
  f.triangle_shading = f.triangles && !scene.triangle_shading.empty();

  f.lights = scene.light_count() > 0;
  // Only materials that some primitive actually uses count.
  std::vector<bool> used(scene.materials.size(), false);
  for (const auto& s : scene.spheres) used[s.material] = true;
  for (const auto& c : scene.cylinders) used[c.material] = true;
  for (const auto& t : scene.triangles) used[t.material] = true;
  const bool can_bounce = scene.nbounces > 0;
  bool casters = false, receivers = false;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    if (m.texture >= 0) f.textures = true;
    if (can_bounce && (m.flags & MATERIAL_REFRACTIVE)) f.refraction = true;
    if (can_bounce && (m.flags & MATERIAL_REFLECTIVE) && !(m.flags & MATERIAL_REFRACTIVE) && m.reflectivity > 0.0f)
      f.reflection = true;
    if (std::max(m.emission.x, std::max(m.emission.y, m.emission.z)) > 0.0f) f.area_lights = true;
    (material_casts_caustics(m) ? casters : receivers) = true;
  }
  // Path mode samples area lights (rectangles, spheres, emissive shapes);
  // phong sees every light as a delta light.
  if (mode == RenderMode::Path) {
    for (const Light& l : scene.lights) f.area_lights = f.area_lights || !light_type(l.kind).delta;
    f.lights = f.lights || f.area_lights;
  } else {
    f.area_lights = false;
  }
  // Caustics need light -> caster -> receiver -> camera: at least two
  // scattering events, a light, a caster and a receiver.
  if (mode == RenderMode::Binary) {
    f.caustics_reason = "binary mode";
  } else if (mode == RenderMode::Phong && caustics != CausticsMode::On) {
    f.caustics_reason = "phong: only with --caustics on";
  } else if (caustics == CausticsMode::Off) {
    f.caustics_reason = "--caustics off";
  } else if (!f.lights) {
    f.caustics_reason = "no lights";
  } else if (caustics == CausticsMode::On) {
    f.caustics = true;
    f.caustics_reason = "--caustics on";
  } else if (scene.nbounces < 2 || !casters || !receivers) {
    f.caustics_reason = scene.nbounces < 2 ? "nbounces < 2" : !casters ? "no smooth metal or glass" : "no receiving surface";
  } else {
    f.caustics = true;
    f.caustics_reason = "metal or glass, and surfaces to receive";
  }
  return f;
}

std::string SceneFeatures::build_options() const {
  std::string o;
  if (spheres) o += " -DHAS_SPHERES";
  if (cylinders) o += " -DHAS_CYLINDERS";
  if (triangles) o += " -DHAS_TRIANGLES";
  if (lights) o += " -DHAS_LIGHTS";
  if (reflection) o += " -DHAS_REFLECTION";
  if (refraction) o += " -DHAS_REFRACTION";
  if (mode == RenderMode::Path) {
    // The path tracer's libraries compile everything unless told otherwise
    // (tests include them bare); the renderer leaves out what is not there.
    if (!refraction) o += " -DBSDF_WITH_DIELECTRIC=0";
    if (!area_lights) o += " -DPATH_WITH_AREA_LIGHTS=0";
    if (caustics) o += " -DPATH_WITH_CAUSTICS=1";
    if (check_numerics) o += " -DPATH_CHECK_NUMERICS=1";
  }
  if (mode == RenderMode::Phong && caustics) o += " -DPHONG_WITH_CAUSTICS=1";
  if (textures) o += " -DHAS_TEXTURES";
  if (triangle_shading) o += " -DHAS_TRIANGLE_SHADING";
  return o;
}

std::string SceneFeatures::describe() const {
  std::string s = std::string("mode=") + render_mode_name(mode);
  s += " primitives={";
  std::string prims;
  if (spheres) prims += "sphere,";
  if (cylinders) prims += "cylinder,";
  if (triangles) prims += "triangle,";
  if (!prims.empty()) prims.pop_back();
  s += prims + "}";
  s += std::string(" lights=") + (lights ? "yes" : "no");
  s += std::string(" reflection=") + (reflection ? "yes" : "no");
  s += std::string(" refraction=") + (refraction ? "yes" : "no");
  s += std::string(" textures=") + (textures ? "yes" : "no");
  s += std::string(" vertex-data=") + (triangle_shading ? "yes" : "no");
  if (mode == RenderMode::Path) {
    s += std::string(" area-light-sampling=") + (area_lights ? "compiled" : "left out");
    s += std::string(" dielectric-bsdf=") + (refraction ? "compiled" : "left out");
  }
  if (mode != RenderMode::Binary)
    s += std::string(" photon-pass=") + (caustics ? "compiled" : "left out") + " (" + caustics_reason + ")";
  return s;
}

}  // namespace caustica
