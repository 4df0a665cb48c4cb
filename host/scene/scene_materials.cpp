// Materials and textures of the coursework format and its student variants
// (scenes/FORMAT.md, "Materials" and "Textures").
#include <algorithm>
#include <cmath>

#include "host/error.h"
#include "host/scene/scene_reader.h"

namespace caustica::scene_detail {

namespace {

const KeyList kMaterialKeys = {"ks",           "kd",          "specularexponent", "diffusecolor", "specularcolor",
                               "isreflective", "reflectivity", "isrefractive",    "refractiveindex", "ka",
                               "basecolor",    "type",        "albedo",           "ior",          "colour",
                               "color",        "intensity",   "emission",         "emissioncolor", "texture",
                               "texture_file", "texturefile", "textureFilename",  "hasTexture",   "texturepath",
                               "hastexture",   "roughness",   "metallic",         "twosided"};
// Path-tracing parameters of some authors' BRDFs: nothing in the phong model
// or in Material corresponds, and they do not change what the scene is.
const KeyList kMaterialIgnored = {"transmittance", "transmittancecolor", "fresnelreflectance", "fuzz"};
const KeyList kTexturePathKeys = {"texture", "texture_file", "texturefile", "textureFilename", "texturepath"};

enum class Kind { Phong, Diffuse, Metal, Dielectric, Emissive };

int checker_texture(LoadContext& ctx, const glm::vec3& c1, const glm::vec3& c2, float scale) {
  const std::vector<float> key = {c1.x, c1.y, c1.z, c2.x, c2.y, c2.z, scale};
  auto it = ctx.checker_textures.find(key);
  if (it != ctx.checker_textures.end()) return it->second;
  const int index = ctx.textures.checker(c1, c2, scale);
  ctx.checker_textures.emplace(key, index);
  return index;
}

}  // namespace

int read_texture(LoadContext& ctx, const json& v, const std::string& path) {
  const Reader& r = ctx.r;
  if (v.is_string()) return image_texture(ctx, v.get<std::string>(), ctx.dir, path);
  if (!v.is_object())
    r.expected(path, "a texture file name or an object {\"type\": \"checkerboard\", \"color1\", \"color2\", \"scale\"}",
               v);
  r.check_keys(v, path, {"type", "color1", "color2", "scale"});
  const std::string type = lower(r.read_string(v, "type", path));
  if (type != "checkerboard" && type != "checker")
    r.expected(path + "/type", "a procedural texture type: \"checkerboard\"", v["type"]);
  return checker_texture(ctx, r.read_vec3(v, "color1", path, Range::Reflectance, glm::vec3(1.0f)),
                         r.read_vec3(v, "color2", path, Range::Reflectance, glm::vec3(0.0f)),
                         r.read_number(v, "scale", path, Range::Positive, 10.0f));
}

namespace {

Material read_material_object(LoadContext& ctx, const json& m, const std::string& path) {
  const Reader& r = ctx.r;
  r.check_keys(m, path, kMaterialKeys, kMaterialIgnored);
  Kind kind = Kind::Phong;
  if (const json* t = Reader::find(m, "type")) {
    const std::string type = lower(r.string(*t, path + "/type"));
    if (type == "diffuse" || type == "lambertian") kind = Kind::Diffuse;
    else if (type == "metal") kind = Kind::Metal;
    else if (type == "dielectric" || type == "glass") kind = Kind::Dielectric;
    else if (type == "emissive" || type == "light") kind = Kind::Emissive;
    else if (type != "phong")
      r.expected(path + "/type", "a material type: \"diffuse\", \"metal\", \"dielectric\" or \"emissive\"", *t);
  }
  // Typed materials (the "Ray Tracing in One Weekend" style) give an albedo
  // that is the whole reflectance: no extra kd factor and no phong highlight
  // unless asked for.
  const bool typed = kind != Kind::Phong;
  const glm::vec3 no_colour = kind == Kind::Emissive ? glm::vec3(0.0f) : glm::vec3(0.8f);
  const char* which = nullptr;
  KeyList colour_keys = {"diffusecolor", "basecolor", "albedo"};
  if (kind != Kind::Emissive) colour_keys.insert(colour_keys.end(), {"colour", "color"});
  const json* colour = Reader::find_any(m, colour_keys, &which);
  const glm::vec3 diffuse = colour ? r.vec3(*colour, path + "/" + which, Range::Reflectance) : no_colour;

  Material out = default_material();
  out.diffuse = to_float4(diffuse, r.read_number(m, "kd", path, Range::Reflectance,
                                                 kind == Kind::Emissive ? 0.0f : typed ? 1.0f : 0.9f));
  out.specular = to_float4(r.read_vec3(m, "specularcolor", path, Range::Reflectance,
                                       kind == Kind::Metal ? diffuse : glm::vec3(1.0f)),
                           r.read_number(m, "ks", path, Range::Reflectance, typed ? 0.0f : 0.1f));
  out.specular_exponent = r.read_number(m, "specularexponent", path, Range::NonNegative, 20.0f);
  out.reflectivity = r.read_number(m, "reflectivity", path, Range::NonNegative, 1.0f);
  const char* ior_key = "refractiveindex";
  const json* ior = Reader::find_any(m, {"refractiveindex", "ior"}, &ior_key);
  out.ka = r.read_number(m, "ka", path, Range::Reflectance, kind == Kind::Emissive ? 0.0f : kDefaultAmbient);
  if (r.read_bool(m, "isreflective", path, kind == Kind::Metal)) out.flags |= MATERIAL_REFLECTIVE;
  if (r.read_bool(m, "isrefractive", path, kind == Kind::Dielectric)) out.flags |= MATERIAL_REFRACTIVE;
  // Files fill in every key, so an opaque material may say 0 here: the index
  // must be positive only where it is used.
  const bool refractive = out.flags & MATERIAL_REFRACTIVE;
  out.ior = ior ? r.number(*ior, path + "/" + ior_key, refractive ? Range::Positive : Range::NonNegative)
                : kind == Kind::Dielectric ? 1.5f : 1.0f;
  if (!(out.ior > 0.0f)) out.ior = 1.0f;
  out.roughness = r.read_number(m, "roughness", path, Range::NonNegative, -1.0f);
  if (r.read_bool(m, "twosided", path, false)) out.flags |= MATERIAL_TWO_SIDED;
  out.metallic = r.read_number(m, "metallic", path, Range::NonNegative, 0.0f);
  if (out.metallic > 1.0f) r.expected(path + "/metallic", "a number in [0, 1]", m["metallic"]);

  glm::vec3 emission(0.0f);
  if (const json* e = Reader::find_any(m, {"emission", "emissioncolor"}, &which)) {
    emission = r.vec3(*e, path + "/" + which, Range::NonNegative);
  } else if (kind == Kind::Emissive) {
    const json* c = Reader::find_any(m, {"colour", "color"}, &which);
    emission = (c ? r.vec3(*c, path + "/" + which, Range::NonNegative) : glm::vec3(1.0f)) *
               r.read_number(m, "intensity", path, Range::NonNegative, 1.0f);
  }
  if (kind != Kind::Emissive && Reader::find(m, "intensity"))
    r.warn_once("material-intensity", path + "/intensity",
                "\"intensity\" only applies to materials of type \"emissive\"; ignored");
  out.emission = to_float4(emission);

  const bool enabled = r.read_bool(m, "hasTexture", path, r.read_bool(m, "hastexture", path, true));
  if (const json* t = Reader::find_any(m, kTexturePathKeys, &which); t && enabled)
    out.texture = read_texture(ctx, *t, path + "/" + which);
  return out;
}

}  // namespace

Material default_material() {
  Material out = blank_material();
  out.diffuse = to_float4(glm::vec3(0.8f), 0.9f);
  out.specular = to_float4(glm::vec3(1.0f), 0.1f);
  out.emission = to_float4(glm::vec3(0.0f));
  out.specular_exponent = 20.0f;
  out.reflectivity = 1.0f;
  out.ka = kDefaultAmbient;
  out.metallic = 0.0f;
  return out;
}

int image_texture(LoadContext& ctx, const std::string& written, const std::string& folder, const std::string& path) {
  const std::string key = folder + "\n" + written;
  if (auto it = ctx.image_textures.find(key); it != ctx.image_textures.end()) return it->second;
  std::string use = written;
  // Authors' absolute paths and working-directory-relative paths: look for
  // the file under the scene's folder before giving up on it.
  if (resolve_texture_path(written, folder).empty())
    if (std::string found = ctx.assets.find(written, "textures"); !found.empty()) use = found;
  std::vector<std::string> warnings;
  const int index = ctx.textures.image(use, folder, ctx.r.file() + ": " + path + ": warning", warnings);
  for (const std::string& w : warnings) ctx.r.forward_warning(w);
  ctx.image_textures.emplace(key, index);
  return index;
}

Material read_shape_material(LoadContext& ctx, const json& shape, const std::string& shape_path, const char* key) {
  static const json kEmpty = json::object();
  const json* v = Reader::find(shape, key);
  const std::string path = shape_path + "/" + key;
  Material out = read_material_object(ctx, v ? ctx.r.object(*v, path) : kEmpty, path);
  // One repository puts the texture on the shape: it is the more specific.
  if (const json* t = Reader::find(shape, "texture")) out.texture = read_texture(ctx, *t, shape_path + "/texture");
  return out;
}

Material mesh_material(LoadContext& ctx, const MeshMaterial& m, const std::string& mesh_dir,
                       const std::string& path) {
  Material out = default_material();
  out.diffuse = to_float4(glm::max(m.kd, glm::vec3(0.0f)), 1.0f);
  const bool shiny = m.ks.x > 0.0f || m.ks.y > 0.0f || m.ks.z > 0.0f;
  out.specular = to_float4(glm::max(m.ks, glm::vec3(0.0f)), shiny ? 1.0f : 0.0f);
  out.specular_exponent = std::max(m.ns, 0.0f);
  out.emission = to_float4(glm::max(m.ke, glm::vec3(0.0f)));
  if (!m.diffuse_texture.empty()) out.texture = image_texture(ctx, m.diffuse_texture, mesh_dir, path);
  return out;
}

}  // namespace caustica::scene_detail
