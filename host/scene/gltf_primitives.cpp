// Mesh primitives to triangles: TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN,
// indexed or not (points and lines are skipped with a warning). Positions,
// NORMAL and the texture coordinate set the material reads (TEXCOORD_0
// unless its textures name another) are read through the checked accessors
// (gltf_accessors.cpp); the node's world transform is applied here, with
// normals by its inverse transpose and the winding swapped under a
// mirroring transform so that front faces stay front faces.
#include <cmath>

#include "host/limits.h"
#include "host/scene/gltf_internal.h"
#include "host/scene/mesh_internal.h"
#include "host/scene/mesh_tangents.h"
#include "host/scene/scene.h"

namespace caustica::gltf_detail {

namespace {

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS: return "POINTS (0)";
    case TINYGLTF_MODE_LINE: return "LINES (1)";
    case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP (2)";
    case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP (3)";
    default: return nullptr;
  }
}

// Corner indices (three per triangle) of `n` vertices in `mode`.
std::vector<uint32_t> triangle_corners(int mode, const std::vector<uint32_t>& v) {
  std::vector<uint32_t> out;
  const size_t n = v.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    out.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    // Every other triangle reversed so that all keep the first one's winding.
    for (size_t i = 0; i + 2 < n; ++i)
      out.insert(out.end(), i % 2 ? std::initializer_list<uint32_t>{v[i + 1], v[i], v[i + 2]}
                                  : std::initializer_list<uint32_t>{v[i], v[i + 1], v[i + 2]});
  } else {  // TRIANGLE_FAN
    for (size_t i = 1; i + 1 < n; ++i) out.insert(out.end(), {v[0], v[i], v[i + 1]});
  }
  return out;
}

void warn_unused_attributes(Context& ctx, const tinygltf::Primitive& prim, const std::string& pp) {
  for (const auto& [name, accessor] : prim.attributes) {
    (void)accessor;
    // Texture coordinate sets a material does not read are merely unused.
    if (name == "POSITION" || name == "NORMAL" || name.rfind("TEXCOORD_", 0) == 0 || name == "TANGENT" ||
        name == "COLOR_0")
      continue;
    const std::string group = name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0 ? "skin attributes"
                                                                                               : "attribute " + name;
    ctx.warn_once(group, pp + "/attributes/" + name,
                  "vertex attribute " + name + " is not supported; ignored" +
                      (name.rfind("COLOR_", 0) == 0 ? " (COLOR_0 tints the base colour)" : ""));
  }
  if (!prim.targets.empty())
    ctx.warn_once("morph targets", pp + "/targets", "morph targets are not supported; the base mesh is rendered");
}

// One tangent per corner of d for its material's normal map: the
// primitive's TANGENT attribute where it has one, else MikkTSpace's.
// Without texture coordinates a normal map has nowhere to be read from.
std::vector<glm::vec4> corner_tangents(Context& ctx, const tinygltf::Primitive& prim, const DecodedPrimitive& d) {
  if (d.uv.empty()) {
    ctx.warn_once("normal map without uv", d.pointer + "/attributes",
                  "a normal-mapped material on a primitive without TEXCOORD_0; the normal map is ignored there");
    return {};
  }
  std::vector<glm::vec4> out;
  if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
    const std::vector<glm::vec4> t = read_tangent_accessor(ctx, it->second, d.pointer + "/attributes/TANGENT");
    if (t.size() != d.p.size())
      ctx.fail(d.pointer + "/attributes/TANGENT", "expected as many elements as POSITION (" +
                                                      std::to_string(d.p.size()) + "), got " + std::to_string(t.size()));
    out.reserve(d.corners.size());
    for (uint32_t v : d.corners) out.push_back(t[v]);
    return out;
  }
  return mikktspace_corner_tangents(d.p, d.n, d.uv, d.corners);
}

// A mesh's primitives as read from their accessors, once per mesh however
// many nodes place it: instancing costs a transform per triangle, not a
// re-read (a graph placing a big mesh 2^20 times must not read it as often).
const std::vector<DecodedPrimitive>& decoded_mesh(Context& ctx, size_t mi) {
  auto cached = ctx.decoded_meshes.find(mi);
  if (cached != ctx.decoded_meshes.end()) return cached->second;
  std::vector<DecodedPrimitive>& out = ctx.decoded_meshes[mi];
  const tinygltf::Mesh& mesh = ctx.model.meshes[mi];
  for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = mesh.primitives[pi];
    const std::string pp = "/meshes/" + std::to_string(mi) + "/primitives/" + std::to_string(pi);
    if (const char* name = mode_name(prim.mode)) {
      ctx.warn_once(std::string("mode ") + name, pp + "/mode",
                    std::string("primitive mode ") + name + " is not supported (only triangles); skipped");
      continue;
    }
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN)
      ctx.fail(pp + "/mode", "expected a primitive mode from 0 to 6, got " + std::to_string(prim.mode));
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) {
      ctx.warn_once("no position", pp + "/attributes", "primitive without POSITION; skipped");
      continue;
    }
    warn_unused_attributes(ctx, prim, pp);
    DecodedPrimitive d;
    d.material = prim.material < 0 ? -1 : static_cast<int>(checked_index(ctx, prim.material, ctx.model.materials.size(),
                                                                       pp + "/material", "materials"));
    d.p = read_vec3_accessor(ctx, position->second, pp + "/attributes/POSITION");
    auto same_count = [&](size_t count, const char* name) {
      if (count != d.p.size())
        ctx.fail(pp + "/attributes/" + name, "expected as many elements as POSITION (" + std::to_string(d.p.size()) +
                                                 "), got " + std::to_string(count));
    };
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      d.n = read_vec3_accessor(ctx, it->second, pp + "/attributes/NORMAL");
      same_count(d.n.size(), "NORMAL");
    }
    // The set the material's textures name (convert_materials), else 0.
    const int uv_set = d.material >= 0 ? ctx.material_uv_set[size_t(d.material)] : 0;
    std::string uv_name = "TEXCOORD_" + std::to_string(uv_set);
    if (uv_set != 0 && !prim.attributes.count(uv_name)) {
      ctx.warn_once("missing uv set", pp + "/attributes", "the material's textures read " + uv_name +
                                                              ", which the primitive lacks; TEXCOORD_0 is used");
      uv_name = "TEXCOORD_0";
    }
    if (auto it = prim.attributes.find(uv_name); it != prim.attributes.end()) {
      d.uv = read_texcoord_accessor(ctx, it->second, pp + "/attributes/" + uv_name);
      same_count(d.uv.size(), uv_name.c_str());
    }
    if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) {
      d.colours = read_colour_accessor(ctx, it->second, pp + "/attributes/COLOR_0");
      same_count(d.colours.size(), "COLOR_0");
    }
    std::vector<uint32_t> vertices;
    if (prim.indices >= 0) {
      vertices = read_index_accessor(ctx, prim.indices, d.p.size(), pp + "/indices");
    } else {
      vertices.resize(d.p.size());
      for (size_t i = 0; i < d.p.size(); ++i) vertices[i] = static_cast<uint32_t>(i);
    }
    if (prim.mode == TINYGLTF_MODE_TRIANGLES && vertices.size() % 3 != 0)
      ctx.warn_once("partial triangle", pp, std::to_string(vertices.size()) +
                                                " vertices is not a multiple of 3; the last " +
                                                std::to_string(vertices.size() % 3) + " ignored");
    d.corners = triangle_corners(prim.mode, vertices);
    d.pointer = pp;
    // Materials were mapped first (gltf_read.cpp): a base or coat normal map.
    if (d.material >= 0 && (ctx.out.materials[size_t(d.material)].normal_texture >= 0 ||
                            ctx.out.materials[size_t(d.material)].clearcoat_normal_texture >= 0))
      d.corner_tangents = corner_tangents(ctx, prim, d);
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace

void add_mesh_instance(Context& ctx, size_t mi, const glm::dmat4& world) {
  const glm::dmat3 linear(world);
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const bool mirrored = glm::determinant(linear) < 0.0;
  // cross(M n, M t) turns over under a mirroring M: so does the bitangent's sign.
  const float handedness = mirrored ? -1.0f : 1.0f;
  Mesh& out = ctx.out.mesh;
  for (const DecodedPrimitive& d : decoded_mesh(ctx, mi)) {
    // Counted before degenerate ones are dropped: the work, not the result.
    if (out.source_faces + d.corners.size() / 3 > limits::kMaxGltfTriangles)
      ctx.fail(d.pointer, "the file's mesh instances add more than " + std::to_string(limits::kMaxGltfTriangles) +
                              " triangles (the limit)");
    out.source_faces += d.corners.size() / 3;
    for (size_t t = 0; t + 2 < d.corners.size(); t += 3) {
      glm::vec3 tp[3], tn[3];
      glm::vec2 tuv[3];
      glm::vec4 tt[3], tc[3];
      for (int k = 0; k < 3; ++k) {
        const size_t corner = t + size_t(mirrored && k > 0 ? 3 - k : k);
        const uint32_t v = d.corners[corner];
        const glm::dvec3 placed(world * glm::dvec4(d.p[v], 1.0));
        if (!within_coordinate_limit(placed))
          ctx.fail(d.pointer, "a node's world transform places vertex " + std::to_string(v) + " " +
                                  beyond_coordinate_limit(placed));
        tp[k] = glm::vec3(placed);
        if (!d.n.empty()) tn[k] = glm::vec3(normal_matrix * glm::dvec3(d.n[v]));
        if (!d.uv.empty()) tuv[k] = d.uv[v];
        if (!d.colours.empty()) tc[k] = d.colours[v];
        if (!d.corner_tangents.empty()) {
          const glm::vec4& ct = d.corner_tangents[corner];
          tt[k] = glm::vec4(glm::vec3(linear * glm::dvec3(glm::vec3(ct))), handedness * ct.w);
        }
      }
      mesh_internal::add_triangle(out, tp, d.n.empty() ? nullptr : tn, d.uv.empty() ? nullptr : tuv, d.material,
                                  d.corner_tangents.empty() ? nullptr : tt, d.colours.empty() ? nullptr : tc);
    }
  }
}

}  // namespace caustica::gltf_detail
