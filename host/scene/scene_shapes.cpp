// Shapes of the coursework format and its student variants (scenes/FORMAT.md,
// "Shapes"): spheres and cylinders stay analytic, everything else becomes
// triangles, with per-triangle shading data where a shape has UVs or normals.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "host/error.h"
#include "host/scene/gltf.h"
#include "host/scene/mesh_internal.h"
#include "host/scene/scene_reader.h"

namespace caustica::scene_detail {

namespace {

constexpr const char* kShapeTypes =
    "a shape type: \"sphere\", \"cylinder\", \"triangle\", \"rectangle\", \"box\", \"mesh\" or \"ply\"";
// Names some authors give shapes for their own tools.
const KeyList kCommonIgnored = {"alias", "name"};
constexpr size_t kWarnLimit = 8;  // a broken mesh-like file should not flood the terminal

glm::vec3 geometric_normal(const glm::vec3 p[3]) { return glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0])); }

TriangleShading make_shading(const glm::vec3 n[3], const glm::vec2 uv[3]) {
  TriangleShading s{};
  s.n0 = to_float4(n[0]);
  s.n1 = to_float4(n[1]);
  s.n2 = to_float4(n[2]);
  s.u0 = uv[0].x, s.v0 = uv[0].y;
  s.u1 = uv[1].x, s.v1 = uv[1].y;
  s.u2 = uv[2].x, s.v2 = uv[2].y;
  return s;
}

const glm::vec2 kDefaultUv[3] = {{0, 0}, {1, 0}, {0, 1}};


}  // namespace

void append_triangle(LoadContext& ctx, const glm::vec3 p[3], cs_uint material, const glm::vec2* uv,
                     const glm::vec3* normals, const glm::vec4* tangents, const glm::vec4* colours) {
  Triangle t{};
  t.v0 = to_float4(p[0]);
  t.v1 = to_float4(p[1]);
  t.v2 = to_float4(p[2]);
  t.material = material;
  ctx.scene.triangles.push_back(t);
  const glm::vec3 n = geometric_normal(p);
  const glm::vec3 flat[3] = {n, n, n};
  ctx.shading.push_back(make_shading(normals ? normals : flat, uv ? uv : kDefaultUv));
  if (uv || normals) ctx.any_shading = true;
  TriangleTangents t4{};
  if (tangents) {
    t4 = {to_float4(glm::vec3(tangents[0]), tangents[0].w), to_float4(glm::vec3(tangents[1]), tangents[1].w),
          to_float4(glm::vec3(tangents[2]), tangents[2].w)};
    ctx.any_tangents = true;
  }
  ctx.tangents.push_back(t4);
  ctx.colours.push_back(vertex_colours(colours));
  if (colours) ctx.any_colours = true;
}

void finish_shading(LoadContext& ctx) {
  if (ctx.any_shading)
    ctx.scene.triangle_shading = std::move(ctx.shading);
  else
    ctx.scene.triangle_shading.clear();
  if (ctx.any_tangents)
    ctx.scene.triangle_tangents = std::move(ctx.tangents);
  else
    ctx.scene.triangle_tangents.clear();
  if (ctx.any_colours)
    ctx.scene.triangle_colours = std::move(ctx.colours);
  else
    ctx.scene.triangle_colours.clear();
}

namespace {

class ShapeReader {
 public:
  explicit ShapeReader(LoadContext& ctx) : ctx_(ctx), r_(ctx.r), out_(ctx.scene) {}

  void read(const json& s, const std::string& path) {
    const std::string type = lower(r_.string(r_.require(s, "type", path + "/type", kShapeTypes), path + "/type"));
    if (type == "sphere" || type == "uvsphere") {
      r_.check_keys(s, path, {"type", "material", "texture", "center", "radius"}, kCommonIgnored);
      Sphere sp{};
      const glm::vec3 center = r_.read_vec3(s, "center", path, Range::Coordinate);  // read in the file's order
      sp.center_radius = to_float4(center, r_.read_number(s, "radius", path, Range::Size));
      sp.material = material(s, path);
      out_.spheres.push_back(sp);
    } else if (type == "cylinder" || type == "uvcylinder") {
      cylinder(s, path);
    } else if (type == "triangle") {
      triangle(s, path);
    } else if (type == "rectangle") {
      rectangle(s, path);
    } else if (type == "box") {
      box(s, path);
    } else if (type == "mesh" || type == "ply") {
      mesh(s, path);
    } else if (type == "cubemap" || type == "sphericalmap") {
      // One renderer's environment-mapped spheres: drawing them as plain
      // spheres would put opaque balls where the author saw reflections.
      r_.warn_once("shape " + type, path,
                   "shape type \"" + type + "\" skipped: environment maps are not supported");
    } else {
      r_.expected(path + "/type", kShapeTypes, s["type"]);
    }
  }

  void finish() {
    if (dropped_ > kWarnLimit)
      r_.warn("/scene/shapes", std::to_string(dropped_) + " zero-area triangles dropped in total");
    finish_shading(ctx_);
  }

 private:
  cs_uint material(const json& s, const std::string& path) {
    return ctx_.materials.add(read_shape_material(ctx_, s, path));
  }

  void add_triangle(const glm::vec3 p[3], cs_uint material, const glm::vec2* uv, const glm::vec3* normals = nullptr) {
    append_triangle(ctx_, p, material, uv, normals);
  }

  // Emitters are one-sided (FORMAT.md). A single emissive triangle or
  // rectangle whose lit side faces away from the camera is nearly always a
  // light written with the other winding (a ceiling light lighting the
  // ceiling), which renders a dark room: say so rather than guess.
  void warn_if_emitting_away_from_camera(const glm::vec3 p[3], cs_uint material, const std::string& path) {
    const Material& m = out_.materials[material];
    const glm::vec3 e = to_vec3(m.emission);
    if (!(std::max({e.x, e.y, e.z}) > 0.0f) || (m.flags & MATERIAL_TWO_SIDED)) return;
    if (glm::dot(geometric_normal(p), out_.camera.position - p[0]) >= 0.0f) return;
    r_.warn(path, "emits only on its front side (v0, v1, v2 counter-clockwise), which faces away from the camera; "
                  "if it should light what the camera sees, list its vertices in the other order or add "
                  "\"twosided\": true to its material");
  }

  bool drop_if_degenerate(const glm::vec3 p[3], const std::string& path, const char* what) {
    if (!degenerate_triangle(p[0], p[1], p[2])) return false;
    if (++dropped_ <= kWarnLimit) r_.warn(path, std::string(what) + " has zero area; dropped");
    return true;
  }

  // Quad a, b, c, d (in order around it) as triangles (a,b,c), (a,c,d) with
  // UVs (0,0), (1,0), (1,1), (0,1).
  void add_quad(const glm::vec3 q[4], cs_uint material, const std::string& path, const char* what) {
    const glm::vec3 t0[3] = {q[0], q[1], q[2]}, t1[3] = {q[0], q[2], q[3]};
    const glm::vec2 uv0[3] = {{0, 0}, {1, 0}, {1, 1}}, uv1[3] = {{0, 0}, {1, 1}, {0, 1}};
    if (!drop_if_degenerate(t0, path, what)) add_triangle(t0, material, uv0);
    if (!drop_if_degenerate(t1, path, what)) add_triangle(t1, material, uv1);
  }

  void cylinder(const json& s, const std::string& path) {
    r_.check_keys(s, path, {"type", "material", "texture", "center", "axis", "radius", "height"},
                  {"alias", "name", "topmaterial", "bottommaterial"});
    Cylinder cy{};
    const glm::vec3 center = r_.read_vec3(s, "center", path, Range::Coordinate);
    cy.center_radius = to_float4(center, r_.read_number(s, "radius", path, Range::Size));
    const glm::dvec3 axis(r_.read_vec3(s, "axis", path, Range::Any));
    const double len = glm::length(axis);
    if (!(len > 0.0)) r_.expected(path + "/axis", "a direction of nonzero length", s["axis"]);
    cy.axis_half = to_float4(glm::vec3(axis / len), r_.read_number(s, "height", path, Range::Size));
    cy.material = material(s, path);
    for (const char* cap : {"topmaterial", "bottommaterial"})
      if (const json* m = Reader::find(s, cap)) {
        r_.object(*m, path + "/" + cap);
        r_.warn_once("cap material", path + "/" + cap,
                     "separate cap materials are not supported; the caps use the side's \"material\"");
      }
    out_.cylinders.push_back(cy);
  }

  void triangle(const json& s, const std::string& path) {
    r_.check_keys(s, path, {"type", "material", "texture", "v0", "v1", "v2", "uv0", "uv1", "uv2"}, kCommonIgnored);
    const glm::vec3 p[3] = {r_.read_vec3(s, "v0", path, Range::Coordinate), r_.read_vec3(s, "v1", path, Range::Coordinate),
                            r_.read_vec3(s, "v2", path, Range::Coordinate)};
    const int uv_count = !!Reader::find(s, "uv0") + !!Reader::find(s, "uv1") + !!Reader::find(s, "uv2");
    glm::vec2 uv[3];
    if (uv_count > 0) {
      for (int i = 0; i < 3; ++i) {
        const std::string key = "uv" + std::to_string(i);
        const json* v = Reader::find(s, key.c_str());
        if (!v)
          r_.fail(path + "/" + key, "required key \"" + key + "\" is missing (expected an array of 2 numbers: uv0, "
                                   "uv1 and uv2 go together)");
        uv[i] = r_.vec2(*v, path + "/" + key, Range::Any);  // beyond [0,1] tiles
      }
    }
    const cs_uint m = material(s, path);  // validated even when the triangle is dropped
    if (drop_if_degenerate(p, path, "triangle")) return;
    add_triangle(p, m, uv_count ? uv : nullptr);
    warn_if_emitting_away_from_camera(p, m, path);
  }

  void rectangle(const json& s, const std::string& path) {
    r_.check_keys(s, path, {"type", "material", "texture", "v0", "v1", "v2", "v3", "corner1", "corner2"},
                  kCommonIgnored);
    glm::vec3 q[4];
    const bool corners = Reader::find(s, "corner1") || Reader::find(s, "corner2");
    if (corners && Reader::find(s, "v0"))
      r_.fail(path, "expected either \"v0\"..\"v3\" or \"corner1\"/\"corner2\", got both");
    if (corners) {
      const glm::vec3 a = r_.read_vec3(s, "corner1", path, Range::Coordinate);
      const glm::vec3 b = r_.read_vec3(s, "corner2", path, Range::Coordinate);
      int flat = -1, flat_count = 0;
      for (int k = 0; k < 3; ++k) {
        const float tolerance = 1e-6f * std::max({1.0f, std::fabs(a[k]), std::fabs(b[k])});
        if (std::fabs(a[k] - b[k]) <= tolerance) flat = k, ++flat_count;
      }
      if (flat_count != 1)
        r_.fail(path + "/corner2", "expected the opposite corner of an axis-aligned rectangle (equal to corner1 in "
                                   "exactly one coordinate), got " + describe(s["corner2"]) + " for corner1 " +
                                       describe(s["corner1"]));
      // Axes a1, a2 follow the flat axis cyclically, so that the normal
      // cross(a1, a2) points along +flat (a floor faces up).
      const int a1 = (flat + 1) % 3, a2 = (flat + 2) % 3;
      const glm::vec3 lo = glm::min(a, b), hi = glm::max(a, b);
      for (int i = 0; i < 4; ++i) {
        q[i][flat] = a[flat];
        q[i][a1] = (i == 1 || i == 2) ? hi[a1] : lo[a1];
        q[i][a2] = (i >= 2) ? hi[a2] : lo[a2];
      }
    } else {
      for (int i = 0; i < 4; ++i) q[i] = r_.read_vec3(s, ("v" + std::to_string(i)).c_str(), path, Range::Coordinate);
    }
    const cs_uint m = material(s, path);
    add_quad(q, m, path, "rectangle");
    const glm::vec3 first[3] = {q[0], q[1], q[2]};
    if (!degenerate_triangle(q[0], q[1], q[2])) warn_if_emitting_away_from_camera(first, m, path);
  }

  void box(const json& s, const std::string& path) {
    r_.check_keys(s, path, {"type", "material", "texture", "min", "max", "rotation"}, kCommonIgnored);
    const glm::vec3 a = r_.read_vec3(s, "min", path, Range::Coordinate), b = r_.read_vec3(s, "max", path, Range::Coordinate);
    // The corpus box has "min" above "max" in two coordinates: corners, really.
    const glm::vec3 lo = glm::min(a, b), hi = glm::max(a, b);
    for (int k = 0; k < 3; ++k)
      if (!(hi[k] > lo[k])) r_.expected(path + "/max", "a corner that differs from \"min\" in every coordinate", s["max"]);
    const glm::mat3 rot = rotation_xyz(r_.read_vec3(s, "rotation", path, Range::Any, glm::vec3(0.0f)));
    glm::vec3 corner[8];
    for (int i = 0; i < 8; ++i)
      corner[i] = rot * glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    // Faces -x, +x, -y, +y, -z, +z, counter-clockwise seen from outside.
    static const int kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    const cs_uint m = material(s, path);
    for (const auto& f : kFaces) {
      const glm::vec3 q[4] = {corner[f[0]], corner[f[1]], corner[f[2]], corner[f[3]]};
      add_quad(q, m, path, "box face");
    }
  }

  float nonzero(float v, const std::string& path, const json& got) {
    if (v == 0.0f) r_.expected(path, "a nonzero scale", got);
    return v;
  }

  glm::vec3 read_scale(const json& obj, const std::string& path) {
    const json* v = Reader::find(obj, "scale");
    if (!v) return glm::vec3(1.0f);
    const std::string p = path + "/scale";
    if (v->is_number()) {
      const float k = nonzero(r_.number(*v, p, Range::Any), p, *v);
      return glm::vec3(k);
    }
    if (!v->is_array() || v->size() != 3) r_.expected(p, "a number or an array of 3 numbers", *v);
    glm::vec3 k = r_.vec3(*v, p, Range::Any);
    for (int i = 0; i < 3; ++i) nonzero(k[i], p + "/" + std::to_string(i), (*v)[i]);
    return k;
  }

  // An inline mesh's arrays (the Python module's load_dict gives NumPy
  // arrays as these): "vertices" [[x, y, z], ...], "indices" [[a, b, c],
  // ...] or flat, and per vertex "normals" [[x, y, z], ...] and "uvs"
  // [[u, v], ...]. Every entry is checked with its JSON pointer.
  Mesh inline_mesh(const json& s, const std::string& path) const {
    const std::string vp = path + "/vertices";
    const json& vertices = r_.array(s.at("vertices"), vp);
    if (vertices.empty()) r_.fail(vp, "expected at least 3 vertices, got none");
    std::vector<glm::vec3> positions;
    positions.reserve(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i)
      positions.push_back(r_.vec3(vertices[i], vp + "/" + std::to_string(i), Range::Coordinate));
    auto per_vertex = [&](const char* key) -> const json* {
      const json* v = Reader::find(s, key);
      if (!v) return nullptr;
      const std::string kp = path + "/" + key;
      r_.array(*v, kp);
      if (v->size() != positions.size())
        r_.fail(kp, "expected one entry per vertex (" + std::to_string(positions.size()) + "), got " +
                        std::to_string(v->size()));
      return v;
    };
    const json* normals_json = per_vertex("normals");
    const json* uvs_json = per_vertex("uvs");
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;
    for (size_t i = 0; normals_json && i < positions.size(); ++i)
      normals.push_back(r_.vec3((*normals_json)[i], path + "/normals/" + std::to_string(i), Range::Any));
    for (size_t i = 0; uvs_json && i < positions.size(); ++i)
      uvs.push_back(r_.vec2((*uvs_json)[i], path + "/uvs/" + std::to_string(i), Range::Any));
    // Indices: triples, or one flat list whose length is a multiple of 3.
    const std::string ip = path + "/indices";
    const json* indices_json = Reader::find(s, "indices");
    if (!indices_json) r_.fail(ip, "required key \"indices\" is missing (expected the triangles' vertex indices, [[a, b, c], ...])");
    const json& indices = r_.array(*indices_json, ip);
    const int last = int(std::min<size_t>(positions.size() - 1, size_t(std::numeric_limits<int>::max())));
    std::vector<uint32_t> corners;
    const bool flat = !indices.empty() && !indices[0].is_array();
    if (flat && indices.size() % 3 != 0)
      r_.fail(ip, "expected a flat list of indices whose length is a multiple of 3, got " +
                      std::to_string(indices.size()));
    for (size_t t = 0; t < indices.size(); ++t) {
      if (flat) {
        corners.push_back(uint32_t(r_.integer(indices[t], ip + "/" + std::to_string(t), 0, last)));
        continue;
      }
      const std::string tp = ip + "/" + std::to_string(t);
      const json& triple = r_.array(indices[t], tp);
      if (triple.size() != 3) r_.fail(tp, "expected 3 vertex indices, got " + std::to_string(triple.size()));
      for (int k = 0; k < 3; ++k)
        corners.push_back(uint32_t(r_.integer(triple[size_t(k)], tp + "/" + std::to_string(k), 0, last)));
    }
    if (corners.empty()) r_.fail(ip, "expected at least one triangle, got none");
    Mesh mesh;
    mesh.source_faces = corners.size() / 3;
    for (size_t t = 0; t < corners.size(); t += 3) {
      glm::vec3 p[3], n[3];
      glm::vec2 uv[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = corners[t + size_t(k)];
        p[k] = positions[v];
        if (!normals.empty()) n[k] = normals[v];
        if (!uvs.empty()) uv[k] = uvs[v];
      }
      mesh_internal::add_triangle(mesh, p, normals.empty() ? nullptr : n, uvs.empty() ? nullptr : uv, -1);
    }
    return mesh;
  }

  void mesh(const json& s, const std::string& path) {
    r_.check_keys(s, path, {"type", "material", "texture", "file", "filename", "path", "transform", "offset", "scale",
                            "euler", "vertices", "indices", "normals", "uvs"},
                  kCommonIgnored);
    const char* file_key = nullptr;
    const json* file = Reader::find_any(s, {"file", "filename", "path"}, &file_key);
    const bool inline_data = Reader::find(s, "vertices") != nullptr;
    if (inline_data && file)
      r_.fail(path, std::string("expected either \"vertices\" (an inline mesh) or \"") + file_key +
                        "\" (a mesh file), got both");
    if (!inline_data)
      for (const char* key : {"indices", "normals", "uvs"})
        if (Reader::find(s, key))
          r_.fail(path + "/" + key, "belongs to an inline mesh, which needs \"vertices\" too");
    if (!file && !inline_data)
      r_.fail(path + "/file", "required key \"file\" is missing (expected the mesh's .obj, .ply, .gltf or .glb file name; "
                              "\"filename\" and \"path\" are accepted too; or an inline mesh's \"vertices\" and "
                              "\"indices\")");
    const std::string file_path = inline_data ? path + "/vertices" : path + "/" + file_key;
    const std::string written = inline_data ? "the inline mesh" : r_.string(*file, file_path);

    // Transform p' = T R S p: "transform" {translate, rotate, scale} or the
    // PLY variant's offset / euler / scale on the shape itself.
    glm::vec3 translate(0.0f), degrees(0.0f), scale(1.0f);
    const json* transform = Reader::find(s, "transform");
    if (transform) {
      if (Reader::find(s, "offset") || Reader::find(s, "euler") || Reader::find(s, "scale"))
        r_.fail(path, "expected either \"transform\" or \"offset\"/\"euler\"/\"scale\", got both");
      const std::string tp = path + "/transform";
      r_.object(*transform, tp);
      r_.check_keys(*transform, tp, {"translate", "rotate", "scale"});
      translate = r_.read_vec3(*transform, "translate", tp, Range::Coordinate, glm::vec3(0.0f));
      degrees = r_.read_vec3(*transform, "rotate", tp, Range::Any, glm::vec3(0.0f));
      scale = read_scale(*transform, tp);
    } else {
      translate = r_.read_vec3(s, "offset", path, Range::Coordinate, glm::vec3(0.0f));
      degrees = r_.read_vec3(s, "euler", path, Range::Any, glm::vec3(0.0f));
      scale = read_scale(s, path);
    }
    const glm::mat3 linear = rotation_xyz(degrees) * glm::mat3(glm::vec3(scale.x, 0, 0), glm::vec3(0, scale.y, 0),
                                                               glm::vec3(0, 0, scale.z));
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    // A mirroring transform turns the winding (and the geometric normal)
    // inside out; swapping two vertices keeps it outward.
    const bool mirrored = glm::determinant(linear) < 0.0f;

    std::string tried;
    const std::string resolved = inline_data ? std::string() : ctx_.assets.find(written, "models", &tried);
    if (!inline_data && resolved.empty())
      r_.fail(file_path, "expected an existing mesh file, got \"" + written + "\" (looked " + tried + ")");
    Scene::MeshInfo info;
    info.file = resolved;  // "" for an inline mesh (its data is the scene's own)
    const bool gltf = !inline_data && is_gltf_file(resolved);
    std::shared_ptr<const Mesh> inline_mesh_data;
    std::shared_ptr<const GltfModel> no_model;
    if (inline_data) inline_mesh_data = std::make_shared<const Mesh>(inline_mesh(s, path));
    std::shared_ptr<const Mesh>& cached = inline_data ? inline_mesh_data : ctx_.meshes[resolved];
    std::shared_ptr<const GltfModel>& model = inline_data ? no_model : ctx_.gltf_models[resolved];
    if (!cached) {
      const auto t0 = std::chrono::steady_clock::now();
      try {
        if (gltf) {
          model = std::make_shared<const GltfModel>(import_gltf(resolved, ctx_.textures));
          cached = std::shared_ptr<const Mesh>(model, &model->mesh);
        } else {
          cached = std::make_shared<const Mesh>(load_mesh(resolved));
        }
      } catch (const Error& e) {
        r_.fail(file_path, std::string("cannot load mesh: ") + e.what());
      }
      info.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (const std::string& w : cached->warnings) r_.warn(file_path, w);
      if (gltf) {
        for (const std::string& w : model->warnings) r_.forward_warning(w);
        // The coursework scene has its own camera and lights.
        if (!model->cameras.empty() || !model->lights.empty())
          r_.warn(file_path, "the glTF file's " + std::to_string(model->cameras.size()) + " cameras and " +
                                 std::to_string(model->lights.size()) +
                                 " punctual lights are not used in a coursework scene (its own camera and "
                                 "lightsources are); only its meshes and materials are placed");
      }
    }
    const Mesh& mesh = *cached;

    // The shape's own material replaces the file's (MTL) materials.
    const bool override_material = Reader::find(s, "material") != nullptr;
    const cs_uint shape_material = override_material ? material(s, path) : 0;
    const std::string mesh_dir =
        inline_data ? ctx_.dir : std::filesystem::path(resolved).parent_path().string();
    // [0]: triangles without a material
    std::vector<int> mtl_ids((gltf ? model->materials.size() : mesh.materials.size()) + 1, -1);
    auto material_of = [&](int m) -> cs_uint {
      if (override_material) return shape_material;
      int& id = mtl_ids[static_cast<size_t>(m + 1)];
      if (id < 0) {
        Material mat = gltf ? (m < 0 ? gltf_default_material() : model->materials[static_cast<size_t>(m)])
                       : m < 0 ? default_material()
                               : mesh_material(ctx_, mesh.materials[static_cast<size_t>(m)], mesh_dir, file_path);
        // A shape-level texture applies to every part of the mesh.
        if (const json* t = Reader::find(s, "texture")) mat.texture = read_texture(ctx_, *t, path + "/texture");
        id = static_cast<int>(ctx_.materials.add(mat));
      }
      return static_cast<cs_uint>(id);
    };

    size_t dropped = 0;
    const float handedness = mirrored ? -1.0f : 1.0f;  // the bitangent turns over with the winding
    for (const MeshTriangle& tri : mesh.triangles) {
      glm::vec3 p[3], n[3];
      glm::vec2 uv[3];
      glm::vec4 tangent[3], colour[3];
      for (int i = 0; i < 3; ++i) {
        const int j = mirrored && i > 0 ? 3 - i : i;
        const glm::dvec3 placed = glm::dmat3(linear) * glm::dvec3(tri.p[j]) + glm::dvec3(translate);
        if (!within_coordinate_limit(placed))
          r_.fail(transform ? path + "/transform" : path,
                  "places triangle " + std::to_string(info.triangles + dropped) + " of " + written + " " +
                      beyond_coordinate_limit(placed));
        p[i] = linear * tri.p[j] + translate;  // in float, as every render so far
        n[i] = tri.has_normals ? glm::normalize(normal_matrix * tri.n[j]) : glm::vec3(0.0f);
        uv[i] = tri.has_uvs ? tri.uv[j] : kDefaultUv[i];
        const glm::vec3 t = linear * glm::vec3(tri.tangent[j]);
        tangent[i] = glm::length(t) > 0.0f ? glm::vec4(glm::normalize(t), handedness * tri.tangent[j].w) : glm::vec4(0.0f);
        colour[i] = tri.colour[j];
      }
      if (degenerate_triangle(p[0], p[1], p[2]) || !std::isfinite(p[0].x + p[1].x + p[2].x)) {
        ++dropped;
        continue;
      }
      const size_t material_count = gltf ? model->materials.size() : mesh.materials.size();
      const bool known = tri.material >= 0 && tri.material < static_cast<int>(material_count);
      const cs_uint m = material_of(known ? tri.material : -1);
      append_triangle(ctx_, p, m, tri.has_uvs || tri.has_normals ? uv : nullptr, tri.has_normals ? n : nullptr,
                      tri.has_tangents ? tangent : nullptr, tri.has_colours ? colour : nullptr);
      ++info.triangles;
    }
    info.dropped_degenerate = mesh.dropped_degenerate + dropped;
    if (dropped > 0)
      r_.warn(file_path, std::to_string(dropped) + " triangles of \"" + written +
                             "\" have zero area after the shape's transform; dropped");
    if (info.triangles == 0) r_.warn(file_path, "mesh \"" + written + "\" adds no triangles");
    out_.meshes.push_back(info);
  }

  LoadContext& ctx_;
  const Reader& r_;
  Scene& out_;
  size_t dropped_ = 0;
};

}  // namespace

// Degrees about x, then y, then z, about the world origin (right-handed):
// R = Rz * Ry * Rx, as in the one corpus file with a rotated box.
glm::mat3 rotation_xyz(const glm::vec3& degrees) {
  const glm::vec3 r = glm::radians(degrees);
  const float cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y);
  const float cz = std::cos(r.z), sz = std::sin(r.z);
  // glm matrices are column-major: each glm::vec3 here is a column.
  const glm::mat3 rx(glm::vec3(1, 0, 0), glm::vec3(0, cx, sx), glm::vec3(0, -sx, cx));
  const glm::mat3 ry(glm::vec3(cy, 0, -sy), glm::vec3(0, 1, 0), glm::vec3(sy, 0, cy));
  const glm::mat3 rz(glm::vec3(cz, sz, 0), glm::vec3(-sz, cz, 0), glm::vec3(0, 0, 1));
  return rz * ry * rx;
}

void read_shapes(LoadContext& ctx, const json& scene_obj) {
  const Reader& r = ctx.r;
  const std::string base = "/scene/shapes";
  const json& shapes = r.array(r.require(scene_obj, "shapes", base, "an array of shapes"), base);
  ShapeReader reader(ctx);
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::string path = base + "/" + std::to_string(i);
    reader.read(r.object(shapes[i], path), path);
  }
  reader.finish();
}

}  // namespace caustica::scene_detail
