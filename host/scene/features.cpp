#include "host/scene/features.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/packing.hpp>

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

namespace {

// The texel scales (lib/material.h's material_texel_scale: x = G^2 for
// alpha, y = B for metallic) at the two ends of m's roughness_texture: the
// smoothest, most metallic corner and the roughest, least metallic one.
// Channels are bounded independently, so a texture whose smoothest texel
// is not its most metallic one still counts as a possible caster: the
// classification errs toward casting (conservative), never away from it.
struct TexelScaleRange {
  float2 smoothest = make_float2(1.0f, 1.0f);
  float2 roughest = make_float2(1.0f, 1.0f);
};

TexelScaleRange texel_scale_range(const Scene& scene, const Material& m) {
  TexelScaleRange r;
  if (m.roughness_texture < 0 || size_t(m.roughness_texture) >= scene.textures.size()) return r;
  const Texture& tex = scene.textures[size_t(m.roughness_texture)];
  float g_lo = 1.0f, g_hi = 0.0f, b_lo = 1.0f, b_hi = 0.0f;
  auto widen = [&](float g, float b) {
    g = std::clamp(g, 0.0f, 1.0f), b = std::clamp(b, 0.0f, 1.0f);  // as the kernel clamps (NaN -> 0 below)
    g_lo = std::min(g_lo, g), g_hi = std::max(g_hi, g), b_lo = std::min(b_lo, b), b_hi = std::max(b_hi, b);
  };
  if (tex.kind == TEXTURE_CHECKER) {
    widen(tex.color1.y, tex.color1.z);
    widen(tex.color2.y, tex.color2.z);
  } else {
    // Bilinear filtering stays within the texels' range.
    const size_t first = size_t(tex.offset) * 4, count = size_t(tex.width) * tex.height;
    for (size_t t = 0; t < count && first + t * 4 + 2 < scene.texels.size(); ++t) {
      const float g = glm::unpackHalf1x16(scene.texels[first + t * 4 + 1]);
      const float b = glm::unpackHalf1x16(scene.texels[first + t * 4 + 2]);
      widen(g == g ? g : 0.0f, b == b ? b : 0.0f);
    }
  }
  if (g_lo > g_hi) return r;  // no texels
  r.smoothest = make_float2(g_lo * g_lo, b_hi);
  r.roughest = make_float2(g_hi * g_hi, b_lo);
  return r;
}

// u_layer picks a partly transmissive material's layer (lib/material.h):
// the largest u below 1 its glass share (if any), 0 its opaque base (if any).
constexpr float kGlassLayer = 0x1.fffffep-1f, kOpaqueLayer = 0.0f;

bool casts(const Material& m, float2 texel_scale, float u_layer) {
  // The coat's textures do not decide whether a surface casts.
  return bsdf_casts_caustics(
      bsdf_of_material(&m, m.diffuse.xyz, make_float4(texel_scale.x, texel_scale.y, 1.0f, 1.0f), u_layer));
}

}  // namespace

// The kernels' own material mapping and caster test (kernels/lib/material.h,
// compiled here through kernels/shared/compat.h): the scene analysis and
// the photon pass cannot disagree about which surfaces cast.
bool material_casts_caustics(const Scene& scene, const Material& m) {
  return casts(m, texel_scale_range(scene, m).smoothest, kGlassLayer);
}

bool material_receives_caustics(const Scene& scene, const Material& m) {
  return !casts(m, texel_scale_range(scene, m).roughest, kOpaqueLayer);
}

SceneFeatures analyse_scene(const Scene& scene, RenderMode mode, CausticsMode caustics) {
  SceneFeatures f;
  f.mode = mode;
  f.spheres = !scene.spheres.empty();
  f.cylinders = !scene.cylinders.empty();
  f.triangles = !scene.triangles.empty();
  // Every mode's rays pass through cut-outs, binary's too.
  for (const Triangle& t : scene.triangles)
    if (scene.materials[t.material].flags & (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND)) {
      f.alpha_cutouts = f.textures = true;  // the traversal reads alpha texels
      break;
    }
  if (mode == RenderMode::Binary) return f;  // binary shading needs no lights, materials or textures
  f.environment = scene.environment.has_value();
  f.materials = true;
  f.triangle_shading = f.triangles && !scene.triangle_shading.empty();
  f.vertex_colours = f.triangles && scene.triangle_colours.size() == scene.triangles.size();

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
    if (m.roughness_texture >= 0 || m.emission_texture >= 0) f.textures = true;
    if (m.clearcoat_texture >= 0 || m.clearcoat_roughness_texture >= 0) f.textures = true;
    if (m.clearcoat > 0.0f) f.clearcoat = true;
    // Tangents come with normal-mapped glTF materials; a normal map without
    // them (a hand-made Material) would have no frame to be read in.
    if ((m.normal_texture >= 0 || m.clearcoat_normal_texture >= 0) && f.triangle_shading &&
        scene.triangle_tangents.size() == scene.triangles.size())
      f.normal_maps = f.textures = true;
    casters = casters || material_casts_caustics(scene, m);
    receivers = receivers || material_receives_caustics(scene, m);
  }
  // Path mode samples area lights (rectangles, spheres, emissive shapes);
  // phong sees every light as a delta light.
  if (mode == RenderMode::Path) {
    for (const Light& l : scene.lights) f.area_lights = f.area_lights || light_type(l.kind).area;
    f.lights = f.lights || f.area_lights || f.environment;
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
  } else if (!f.lights && !f.environment) {  // phong's environment emits photons, though it is no shading light
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

int SceneFeatures::flag_value(FeatureFlag flag) const {
  const bool path = mode == RenderMode::Path;
  switch (flag) {
    case FeatureFlag::kHAS_SPHERES: return spheres;
    case FeatureFlag::kHAS_CYLINDERS: return cylinders;
    case FeatureFlag::kHAS_TRIANGLES: return triangles;
    case FeatureFlag::kHAS_TRIANGLE_SHADING: return triangle_shading;
    case FeatureFlag::kHAS_TEXTURES: return textures;
    case FeatureFlag::kHAS_LIGHTS: return lights;
    case FeatureFlag::kHAS_REFLECTION: return reflection;
    case FeatureFlag::kHAS_REFRACTION: return refraction;
    // The path tracer leaves out what its scene does not have; phong's
    // photon pass keeps both (it may trace glass without refraction rays,
    // and its lights are emitted as the path tracer's are).
    case FeatureFlag::kHAS_DIELECTRIC: return path ? refraction : 1;
    case FeatureFlag::kHAS_AREA_LIGHTS: return path ? area_lights : 1;
    case FeatureFlag::kHAS_CAUSTICS: return caustics;
    case FeatureFlag::kHAS_NUMERIC_CHECKS: return path && check_numerics;
    case FeatureFlag::kHAS_ENVIRONMENT: return environment;
    case FeatureFlag::kHAS_AUX_PASSES: return path && aux_passes;
    case FeatureFlag::kHAS_LIGHT_TREE: return path && light_tree;
    case FeatureFlag::kHAS_NORMAL_MAPS: return normal_maps;
    case FeatureFlag::kHAS_VERTEX_COLOURS: return vertex_colours;
    case FeatureFlag::kHAS_ALPHA_CUTOUTS: return alpha_cutouts;
    // Phong has no clear coat; its photon pass keeps it (as the dielectric).
    case FeatureFlag::kHAS_CLEARCOAT: return path ? clearcoat : 1;
  }
  throw Error("unknown feature flag");
}

std::string SceneFeatures::build_options() const {
  std::string o;
  for (int f = 0; f < kFeatureFlagCount; ++f)
    o += std::string(" -D") + kFeatureFlags[f].name + "=" + std::to_string(flag_value(FeatureFlag(f)));
  return o;
}

std::string SceneFeatures::describe() const {
  std::string s = std::string("mode=") + render_mode_name(mode);
  for (int f = 0; f < kFeatureFlagCount; ++f) {
    s += std::string(" ") + kFeatureFlags[f].word + "=" + (flag_value(FeatureFlag(f)) ? "yes" : "no");
    if (FeatureFlag(f) == FeatureFlag::kHAS_CAUSTICS && !caustics_reason.empty()) s += " (" + caustics_reason + ")";
  }
  return s;
}

}  // namespace caustica
