// glTF materials onto ours (Material, kernels/lib/material.h; the table is
// in scenes/FORMAT.md, "glTF 2.0 files"): pbrMetallicRoughness becomes the
// coated-diffuse plastic moved toward a conductor by `metallic` (F0 from the
// index of refraction, 0.04 by default; GGX alpha = roughness^2);
// KHR_materials_pbrSpecularGlossiness, where a file has it, takes precedence
// (diffuse and specular colours map one to one); KHR_materials_transmission
// makes a dielectric of KHR_materials_ior's index; emissiveFactor times
// KHR_materials_emissive_strength is the emission, values above 1 honoured.
// The metallicRoughnessTexture and the emissiveTexture are sampled per
// texel (Material's roughness_texture and emission_texture);
// specularGlossinessTexture is ignored (warned). A normalTexture perturbs
// the shading normal in the frame of the primitives' tangents
// (kernels/lib/normal_map.h). alphaMode MASK and BLEND become cut-outs in
// the traversal (MATERIAL_ALPHA_*, kernels/lib/alpha_cutout.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "host/scene/gltf_internal.h"
#include "host/scene/scene_reader.h"

namespace caustica::gltf_detail {

namespace {

class MaterialMapper {
 public:
  explicit MaterialMapper(Context& ctx) : ctx_(ctx), m_(ctx.model) {}

  Material map(size_t i) {
    const tinygltf::Material& in = m_.materials[i];
    const std::string mp = "/materials/" + std::to_string(i);
    Material out = scene_detail::default_material();
    const tinygltf::PbrMetallicRoughness& pbr = in.pbrMetallicRoughness;
    const double ior = extension_number(in, "KHR_materials_ior", "ior", 1.5, mp);
    if (!(ior >= 1.0 && ior < 10.0)) ctx_.fail(mp + "/extensions/KHR_materials_ior/ior", "expected an index in [1, 10)");
    const double f0 = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
    glm::vec4 base;
    double roughness;
    auto sg = in.extensions.find("KHR_materials_pbrSpecularGlossiness");
    if (sg != in.extensions.end() && sg->second.IsObject()) {
      const std::string sp = mp + "/extensions/KHR_materials_pbrSpecularGlossiness";
      const tinygltf::Value& v = sg->second;
      base = colour(v, "diffuseFactor", 4, glm::vec4(1.0f), sp);
      out.specular = to_float4(glm::vec3(colour(v, "specularFactor", 3, glm::vec4(1.0f), sp)), 1.0f);
      roughness = 1.0 - number(v, "glossinessFactor", 1.0, sp);
      if (v.Has("diffuseTexture") && v.Get("diffuseTexture").IsObject() && v.Get("diffuseTexture").Has("index"))
        out.texture = texture_of_value(v.Get("diffuseTexture"), sp + "/diffuseTexture");
      if (v.Has("specularGlossinessTexture"))
        ctx_.warn_once("specgloss texture", sp + "/specularGlossinessTexture",
                       "specularGlossinessTexture is not supported (one texture per material); the factors are used");
    } else {
      base = vec4_of(pbr.baseColorFactor, mp + "/pbrMetallicRoughness/baseColorFactor");
      double metallic = unit(pbr.metallicFactor, mp + "/pbrMetallicRoughness/metallicFactor");
      roughness = unit(pbr.roughnessFactor, mp + "/pbrMetallicRoughness/roughnessFactor");
      if (pbr.baseColorTexture.index >= 0)
        out.texture = texture(pbr.baseColorTexture, mp + "/pbrMetallicRoughness/baseColorTexture");
      // Per texel (lib/material.h): roughness x G, metallic x B, linear.
      if (pbr.metallicRoughnessTexture.index >= 0)
        out.roughness_texture = image_texture(ctx_, pbr.metallicRoughnessTexture,
                                              mp + "/pbrMetallicRoughness/metallicRoughnessTexture",
                                              /*linear_data=*/true);
      out.specular = to_float4(glm::vec3(1.0f), static_cast<float>(f0));
      specular(in, out, mp);
      out.metallic = static_cast<float>(metallic);
    }
    if (!(roughness >= 0.0 && roughness <= 1.0)) ctx_.fail(mp, "expected a roughness (1 - glossiness) in [0, 1]");
    const float alpha = static_cast<float>(roughness * roughness);
    out.roughness = alpha;
    // Phong's exponent for the same lobe width (material.h's inverse map).
    out.specular_exponent = alpha > 0.0f ? std::min(2.0f / (alpha * alpha) - 2.0f, 1e4f) : 1e4f;
    out.diffuse = to_float4(glm::vec3(base), 1.0f);
    if (out.texture >= 0) out.flags |= MATERIAL_TEXTURE_SCALES;  // factor x texture, as glTF multiplies them
    alpha_mode(in, base.w, out, mp);
    if (in.doubleSided) out.flags |= MATERIAL_TWO_SIDED;

    const double transmission = extension_number(in, "KHR_materials_transmission", "transmissionFactor", 0.0, mp);
    if (transmission > 1.0) ctx_.fail(mp + "/extensions/KHR_materials_transmission/transmissionFactor",
                                      "expected a number in [0, 1], got " + std::to_string(transmission));
    if (transmission > 0.0) transmission_and_volume(in, transmission, ior, out, mp);
    clearcoat(in, out, mp);
    emission(in, out, mp);
    for (const auto& [name, value] : in.extensions) {
      (void)value;
      if (name != "KHR_materials_ior" && name != "KHR_materials_transmission" &&
          name != "KHR_materials_emissive_strength" && name != "KHR_materials_pbrSpecularGlossiness" &&
          name != "KHR_materials_clearcoat" && name != "KHR_materials_volume" && name != "KHR_materials_specular")
        ctx_.warn_once("material " + name, mp + "/extensions/" + name, "material extension " + name +
                                                                            " is not supported; ignored");
    }
    if (in.normalTexture.index >= 0) normal_map(in.normalTexture, out, mp + "/normalTexture");
    if (in.occlusionTexture.index >= 0)
      ctx_.warn_once("occlusionTexture", mp + "/occlusionTexture",
                     "occlusion maps are not supported (a path tracer computes occlusion); ignored");
    return out;
  }

 private:
  // KHR_materials_transmission's glass (kernels/lib/material.h): the
  // dielectric part of the material (1 - metallic) transmits a share t,
  // tinted by the base colour; the rest is the opaque base, whose metallic
  // is renormalised to the metal's share of it. KHR_materials_volume with a
  // thickness (a volume, not a thin wall) absorbs inside: sigma = -ln(c) / d
  // per channel for attenuationColor c and attenuationDistance d.
  void transmission_and_volume(const tinygltf::Material& in, double t, double ior, Material& out,
                               const std::string& mp) {
    out.flags |= MATERIAL_REFRACTIVE | MATERIAL_TINTED_TRANSMISSION;
    out.ior = static_cast<float>(ior);
    const double glass = t * (1.0 - double(out.metallic));
    out.volume.w = static_cast<float>(1.0 - glass);
    if (glass < 1.0) out.metallic = static_cast<float>(double(out.metallic) / (1.0 - glass));
    if (glass <= 0.0)
      ctx_.warn_once("transmission on metal", mp + "/extensions/KHR_materials_transmission",
                     "transmission on a material of metallicFactor " +
                         (out.metallic == 1.0f ? std::string("1 (glTF's default)") : std::to_string(out.metallic)) +
                         " is no glass (the specification transmits only the dielectric part); set metallicFactor "
                         "0 for glass");
    warn_texture(in, "KHR_materials_transmission", "transmissionTexture", mp);
    auto v = in.extensions.find("KHR_materials_volume");
    if (v == in.extensions.end()) return;
    const std::string vp = mp + "/extensions/KHR_materials_volume";
    warn_texture(in, "KHR_materials_volume", "thicknessTexture", mp);
    if (!(number(v->second, "thicknessFactor", 0.0, vp) > 0.0)) return;  // thin-walled: no volume
    const double distance = v->second.Has("attenuationDistance")
                                ? number(v->second, "attenuationDistance", 0.0, vp)
                                : std::numeric_limits<double>::infinity();
    if (!(distance > 0.0)) ctx_.fail(vp + "/attenuationDistance", "expected a positive number");
    const glm::vec4 c = colour(v->second, "attenuationColor", 3, glm::vec4(1.0f), vp);
    glm::vec3 sigma(0.0f);
    for (int i = 0; i < 3; ++i)
      sigma[i] = c[i] >= 1.0f || std::isinf(distance) ? 0.0f
                 : c[i] <= 0.0f                        ? 1e30f
                                                      : static_cast<float>(-std::log(double(c[i])) / distance);
    if (sigma != glm::vec3(0.0f)) {
      out.flags |= MATERIAL_ATTENUATES;
      out.volume = to_float4(glm::min(sigma, glm::vec3(1e30f)), out.volume.w);
    }
  }

  // KHR_materials_clearcoat (kernels/lib/bsdf.h): the coat's weight and
  // GGX alpha = roughness^2, scaled per texel by its data textures, and its
  // own normal map.
  void clearcoat(const tinygltf::Material& in, Material& out, const std::string& mp) {
    auto c = in.extensions.find("KHR_materials_clearcoat");
    if (c == in.extensions.end()) return;
    const std::string cp = mp + "/extensions/KHR_materials_clearcoat";
    const double weight = number(c->second, "clearcoatFactor", 0.0, cp);
    const double roughness = number(c->second, "clearcoatRoughnessFactor", 0.0, cp);
    if (weight > 1.0) ctx_.fail(cp + "/clearcoatFactor", "expected a number in [0, 1]");
    if (roughness > 1.0) ctx_.fail(cp + "/clearcoatRoughnessFactor", "expected a number in [0, 1]");
    if (out.flags & MATERIAL_REFRACTIVE && out.volume.w <= 0.0f) return;  // all glass: no coat (lib/bsdf.h)
    out.clearcoat = static_cast<float>(weight);
    out.clearcoat_alpha = static_cast<float>(roughness * roughness);
    // Data textures, read per texel (lib/material.h: material_texel_scale).
    if (weight > 0.0 && c->second.Has("clearcoatTexture"))
      out.clearcoat_texture = data_texture(c->second.Get("clearcoatTexture"), cp + "/clearcoatTexture");
    if (weight > 0.0 && c->second.Has("clearcoatRoughnessTexture"))
      out.clearcoat_roughness_texture =
          data_texture(c->second.Get("clearcoatRoughnessTexture"), cp + "/clearcoatRoughnessTexture");
    // The coat's own normal map, in the base's tangent frame (lib/normal_map.h).
    if (weight > 0.0 && c->second.Has("clearcoatNormalTexture")) {
      const tinygltf::Value& info = c->second.Get("clearcoatNormalTexture");
      const std::string np = cp + "/clearcoatNormalTexture";
      out.clearcoat_normal_texture = data_texture(info, np);
      out.clearcoat_normal_scale = static_cast<float>(info.Has("scale") ? signed_number(info, "scale", np) : 1.0);
    }
  }

  // KHR_materials_specular on the metallic-roughness model: the coat's
  // normal reflectance becomes specularColorFactor x F0(ior), at most 1,
  // times specularFactor.
  void specular(const tinygltf::Material& in, Material& out, const std::string& mp) {
    auto s = in.extensions.find("KHR_materials_specular");
    if (s == in.extensions.end()) return;
    const std::string sp = mp + "/extensions/KHR_materials_specular";
    const double factor = number(s->second, "specularFactor", 1.0, sp);
    if (factor > 1.0) ctx_.fail(sp + "/specularFactor", "expected a number in [0, 1]");
    glm::vec3 colour_factor(1.0f);
    if (s->second.Has("specularColorFactor")) {
      const tinygltf::Value& v = s->second.Get("specularColorFactor");
      const std::string p = sp + "/specularColorFactor";
      if (!v.IsArray() || v.ArrayLen() != 3) ctx_.fail(p, "expected 3 numbers");
      for (int i = 0; i < 3; ++i) {
        const tinygltf::Value& e = v.Get(i);
        const double d = e.IsNumber() ? e.GetNumberAsDouble() : NAN;
        if (!(d >= 0.0) || !std::isfinite(d)) ctx_.fail(p + "/" + std::to_string(i), "expected a non-negative number");
        colour_factor[i] = static_cast<float>(d);
      }
    }
    // F0 per channel = min(F0(ior) x colour, 1) x factor; stored as colour x strength.
    const glm::vec3 f0 = glm::min(out.specular.w * colour_factor, glm::vec3(1.0f)) * static_cast<float>(factor);
    const float strength = std::max(f0.x, std::max(f0.y, f0.z));
    out.specular = strength > 0.0f ? to_float4(f0 / strength, strength) : to_float4(glm::vec3(1.0f), 0.0f);
    warn_texture(in, "KHR_materials_specular", "specularTexture", mp);
    warn_texture(in, "KHR_materials_specular", "specularColorTexture", mp);
  }

  void warn_texture(const tinygltf::Material& in, const char* ext, const char* key, const std::string& mp) {
    auto e = in.extensions.find(ext);
    if (e == in.extensions.end() || !e->second.IsObject() || !e->second.Has(key)) return;
    const std::string p = mp + "/extensions/" + ext + "/" + key;
    ctx_.warn_once(std::string(ext) + " " + key, p, std::string(key) + " is not supported; its factor is used alone");
  }

  // alphaMode (kernels/lib/alpha_cutout.h): MASK cuts out where the base
  // colour's alpha (factor x texture) is under alphaCutoff, BLEND passes
  // rays with probability 1 - alpha; OPAQUE ignores alpha, as the
  // specification says.
  void alpha_mode(const tinygltf::Material& in, float factor, Material& out, const std::string& mp) {
    out.alpha_factor = factor;
    if (in.alphaMode == "MASK") {
      if (!(in.alphaCutoff >= 0.0 && std::isfinite(in.alphaCutoff)))
        ctx_.fail(mp + "/alphaCutoff", "expected a non-negative number, got " + std::to_string(in.alphaCutoff));
      out.flags |= MATERIAL_ALPHA_MASK;
      out.alpha_cutoff = static_cast<float>(in.alphaCutoff);
    } else if (in.alphaMode == "BLEND") {
      out.flags |= MATERIAL_ALPHA_BLEND;
    } else if (in.alphaMode != "OPAQUE") {
      ctx_.fail(mp + "/alphaMode", "expected \"OPAQUE\", \"MASK\" or \"BLEND\", got \"" + in.alphaMode + "\"");
    }
  }

  // Tangent-space texels read as data (not sRGB-decoded); the tangents are
  // the primitives' (gltf_primitives.cpp). An unreadable image leaves the
  // surface's own normal, with the texture's warning.
  void normal_map(const tinygltf::NormalTextureInfo& in, Material& out, const std::string& pointer) {
    tinygltf::TextureInfo info;
    info.index = in.index;
    info.texCoord = in.texCoord;
    info.extensions = in.extensions;
    out.normal_texture = image_texture(ctx_, info, pointer, /*linear_data=*/true);
    if (!std::isfinite(in.scale) || std::fabs(in.scale) > 1e3)
      ctx_.fail(pointer + "/scale", "expected a finite number (at most 1000 in size), got " + std::to_string(in.scale));
    out.normal_scale = static_cast<float>(in.scale);
  }

  void emission(const tinygltf::Material& in, Material& out, const std::string& mp) {
    glm::vec3 e(0.0f);
    if (!in.emissiveFactor.empty()) {
      const std::string ep = mp + "/emissiveFactor";
      if (in.emissiveFactor.size() != 3) ctx_.fail(ep, "expected 3 numbers");
      for (int c = 0; c < 3; ++c) e[c] = static_cast<float>(in.emissiveFactor[size_t(c)]);
      // Above glTF's [0, 1]: assimp writes an OBJ's Ke there (17 for the
      // Cornell box's light); honoured, so a converted scene stays lit.
      if (!(e.x >= 0.0f && e.y >= 0.0f && e.z >= 0.0f && std::isfinite(e.x + e.y + e.z)))
        ctx_.fail(ep, "expected non-negative finite numbers");
    }
    e *= static_cast<float>(extension_number(in, "KHR_materials_emissive_strength", "emissiveStrength", 1.0, mp));
    if (!std::isfinite(e.x + e.y + e.z)) ctx_.fail(mp, "emission (emissiveFactor x emissiveStrength) overflows");
    out.emission = to_float4(e);
    // Per texel (lib/material.h, lib/lights/triangle_light.h): sRGB-decoded
    // as a colour; no factor, no emission, so no texture to read.
    if (in.emissiveTexture.index >= 0 && glm::any(glm::greaterThan(e, glm::vec3(0.0f))))
      out.emission_texture = texture(in.emissiveTexture, mp + "/emissiveTexture");
  }

  double number(const tinygltf::Value& obj, const char* key, double fallback, const std::string& pointer) {
    if (!obj.IsObject() || !obj.Has(key)) return fallback;
    const tinygltf::Value& v = obj.Get(key);
    const double d = v.IsNumber() ? v.GetNumberAsDouble() : NAN;
    if (!std::isfinite(d) || d < 0.0) ctx_.fail(pointer + "/" + key, "expected a non-negative number");
    return d;
  }

  double signed_number(const tinygltf::Value& obj, const char* key, const std::string& pointer) {
    const tinygltf::Value& v = obj.Get(key);
    const double d = v.IsNumber() ? v.GetNumberAsDouble() : NAN;
    if (!std::isfinite(d) || std::fabs(d) > 1e3)
      ctx_.fail(pointer + "/" + key, "expected a finite number (at most 1000 in size)");
    return d;
  }

  double extension_number(const tinygltf::Material& in, const char* ext, const char* key, double fallback,
                          const std::string& mp) {
    auto it = in.extensions.find(ext);
    return it == in.extensions.end() ? fallback : number(it->second, key, fallback, mp + "/extensions/" + ext);
  }

  double unit(double v, const std::string& pointer) {
    if (!(v >= 0.0 && v <= 1.0)) ctx_.fail(pointer, "expected a number in [0, 1], got " + std::to_string(v));
    return v;
  }

  glm::vec4 vec4_of(const std::vector<double>& v, const std::string& pointer) {
    if (v.size() != 4) ctx_.fail(pointer, "expected 4 numbers");
    glm::vec4 out;
    for (int c = 0; c < 4; ++c) out[c] = static_cast<float>(unit(v[size_t(c)], pointer + "/" + std::to_string(c)));
    return out;
  }

  glm::vec4 colour(const tinygltf::Value& obj, const char* key, int n, glm::vec4 fallback, const std::string& sp) {
    if (!obj.Has(key)) return fallback;
    const tinygltf::Value& v = obj.Get(key);
    const std::string p = sp + "/" + key;
    if (!v.IsArray() || v.ArrayLen() != size_t(n)) ctx_.fail(p, "expected " + std::to_string(n) + " numbers");
    for (int c = 0; c < n; ++c) {
      const tinygltf::Value& e = v.Get(c);
      fallback[c] = static_cast<float>(unit(e.IsNumber() ? e.GetNumberAsDouble() : NAN, p + "/" + std::to_string(c)));
    }
    return fallback;
  }

  // A textureInfo written inside an extension, read as data (linear texels).
  int data_texture(const tinygltf::Value& info, const std::string& pointer) {
    if (!info.IsObject() || !info.Has("index")) ctx_.fail(pointer, "expected a textureInfo object with an index");
    return image_texture(ctx_, texture_info_of(info), pointer, /*linear_data=*/true);
  }

  static tinygltf::TextureInfo texture_info_of(const tinygltf::Value& info) {
    tinygltf::TextureInfo t;
    const tinygltf::Value& i = info.Get("index");
    t.index = i.IsNumber() && std::fabs(i.GetNumberAsDouble()) < 1e9 ? int(i.GetNumberAsDouble()) : -1;
    if (info.Has("texCoord") && info.Get("texCoord").IsNumber()) t.texCoord = int(info.Get("texCoord").GetNumberAsDouble());
    return t;
  }

  int texture_of_value(const tinygltf::Value& info, const std::string& pointer) {
    return texture(texture_info_of(info), pointer);
  }

  int texture(const tinygltf::TextureInfo& info, const std::string& pointer) {
    return image_texture(ctx_, info, pointer);
  }

  Context& ctx_;
  const tinygltf::Model& m_;
};

}  // namespace

// A material's textures may name any TEXCOORD_n: its primitives then read
// that set as their texture coordinates. One set per material (a triangle
// carries one): textures naming several are read with the smallest, warned.
void convert_materials(Context& ctx) {
  MaterialMapper mapper(ctx);
  const size_t n = ctx.model.materials.size();
  ctx.uv_sets_named.assign(n, {});
  ctx.material_uv_set.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    ctx.mapping_material = static_cast<int>(i);
    ctx.out.materials.push_back(mapper.map(i));
    const std::set<int>& sets = ctx.uv_sets_named[i];
    if (sets.empty()) continue;
    ctx.material_uv_set[i] = *sets.begin();
    if (sets.size() > 1)
      ctx.warn_once("texCoord", "/materials/" + std::to_string(i),
                    "the material's textures read " + std::to_string(sets.size()) +
                        " texture coordinate sets; one set per material is supported: TEXCOORD_" +
                        std::to_string(*sets.begin()) + " is used for all");
  }
  ctx.mapping_material = -1;
}

}  // namespace caustica::gltf_detail
