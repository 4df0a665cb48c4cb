// Wavefront OBJ through Debian's tinyobjloader (the shared library carries
// the implementation, so TINYOBJLOADER_IMPLEMENTATION must not be defined).
//
// tinyobjloader is asked NOT to triangulate: its built-in ear clipper (2.0
// rc10) can emit triangles outside concave polygons, and only untriangulated
// output still tells how many faces the file had. It also passes
// out-of-range indices through with nothing but a warning, so every index is
// checked here before it is used.
#include <tiny_obj_loader.h>

#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/scene/mesh_internal.h"

namespace caustica::mesh_internal {

namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// Between "[ " and " ]" in tinyobjloader's messages, or empty.
std::string bracketed(const std::string& line) {
  const size_t b = line.find("[ "), e = line.find(" ]");
  if (b == std::string::npos || e == std::string::npos || e < b + 2) return {};
  std::string s = line.substr(b + 2, e - b - 2);
  if (s.size() >= 2 && s.front() == '\'' && s.back() == '\'') s = s.substr(1, s.size() - 2);
  return s;
}

// Says what the two common material problems mean for the render.
std::string reword(const std::string& line) {
  const std::string name = bracketed(line);
  if (name.empty()) return line;
  if (line.rfind("Material file", 0) == 0) {
    const size_t dir = line.find(" : ");
    return "material library '" + name + "' not found" +
           (dir == std::string::npos ? "" : " in '" + line.substr(dir + 3) + "'") +
           "; its materials are missing and their faces use the default material";
  }
  if (line.rfind("material [", 0) == 0)
    return "usemtl '" + name + "' names no loaded material; its faces use the default material";
  return line;
}

// tinyobjloader reports faces with fewer than 3 corners only as warnings;
// they are counted as degenerate faces instead. Warnings about MTL features
// the renderer ignores (d vs Tr) are noise. The rest is passed on once per
// distinct text, so a broken file cannot flood the log.
void collect_warnings(const std::string& path, const std::string& text, Mesh& mesh) {
  std::vector<std::string> order;
  std::map<std::string, size_t> counts;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.empty() || line == ".") continue;
    if (line.rfind("Degenerated face found", 0) == 0) {
      ++mesh.source_faces;
      ++mesh.dropped_degenerate;
      continue;
    }
    if (line.find("Both `d` and `Tr`") != std::string::npos) continue;
    if (line.rfind("Failed to load material file(s)", 0) == 0) continue;  // repeats the line before it
    line = reword(line);
    if (counts[line]++ == 0) order.push_back(line);
  }
  for (const auto& w : order) {
    const size_t c = counts[w];
    mesh.warnings.push_back(path + ": " + w + (c > 1 ? " (" + std::to_string(c) + " times)" : ""));
  }
}

std::string resolve_texture(const std::string& obj_dir, const std::string& tex) {
  if (tex.empty() || obj_dir.empty()) return tex;
  const std::filesystem::path p(tex);
  if (p.is_absolute()) return tex;
  return (std::filesystem::path(obj_dir) / p).generic_string();
}

}  // namespace

Mesh load_obj(const std::string& path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string msg = trim(reader.Error());
    throw Error(path + ": cannot read OBJ file" + (msg.empty() ? "" : ": " + msg));
  }

  Mesh mesh;
  collect_warnings(path, reader.Warning(), mesh);
  // tinyobjloader collects MTL errors (it has none in practice) next to parse
  // errors without failing; they are only worth a warning.
  if (const std::string err = trim(reader.Error()); !err.empty()) mesh.warnings.push_back(path + ": " + err);

  const std::string obj_dir = std::filesystem::path(path).parent_path().string();
  for (const auto& m : reader.GetMaterials()) {
    MeshMaterial mm;
    mm.name = m.name;
    mm.kd = glm::vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    mm.ks = glm::vec3(m.specular[0], m.specular[1], m.specular[2]);
    mm.ke = glm::vec3(m.emission[0], m.emission[1], m.emission[2]);
    mm.ns = m.shininess;
    mm.diffuse_texture = resolve_texture(obj_dir, m.diffuse_texname);
    mesh.materials.push_back(std::move(mm));
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const auto& vs = attrib.vertices;
  const auto& ns = attrib.normals;
  const auto& ts = attrib.texcoords;
  const long long nv = static_cast<long long>(vs.size() / 3);
  const long long nn = static_cast<long long>(ns.size() / 3);
  const long long nt = static_cast<long long>(ts.size() / 2);
  const int nmat = static_cast<int>(mesh.materials.size());

  size_t total_faces = 0;
  for (const auto& shape : reader.GetShapes()) total_faces += shape.mesh.num_face_vertices.size();
  mesh.source_faces += total_faces;
  mesh.triangles.reserve(total_faces + total_faces / 8);

  std::vector<glm::vec3> pos, nrm;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> tris;
  size_t face_number = 0;  // 1-based, over the whole file, for messages
  for (const auto& shape : reader.GetShapes()) {
    const auto& m = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      ++face_number;
      const size_t count = m.num_face_vertices[f];
      auto fail = [&](const char* what, long long index, long long available) {
        // Reported 1-based, after resolving negative (relative) indices.
        const std::string where = path + ": face " + std::to_string(face_number) +
                                  (shape.name.empty() ? "" : " (group '" + shape.name + "')") + ": ";
        if (index < 0) throw Error(where + "a relative " + what + " index reaches before the first one");
        throw Error(where + what + " index " + std::to_string(index + 1) + " is out of range " +
                    (available > 0 ? "(1.." + std::to_string(available) + ")" : "(the file defines none)"));
      };
      pos.clear();
      nrm.clear();
      uvs.clear();
      bool has_n = true, has_uv = true;
      for (size_t k = 0; k < count; ++k) {
        const tinyobj::index_t& idx = m.indices[offset + k];
        if (idx.vertex_index < 0 || idx.vertex_index >= nv) fail("vertex", idx.vertex_index, nv);
        // tinyobjloader uses -1 for "not given"; anything else must exist.
        if (idx.normal_index < -1 || idx.normal_index >= nn) fail("normal", idx.normal_index, nn);
        if (idx.texcoord_index < -1 || idx.texcoord_index >= nt) fail("texture coordinate", idx.texcoord_index, nt);
        const size_t vi = static_cast<size_t>(idx.vertex_index);
        pos.emplace_back(vs[3 * vi], vs[3 * vi + 1], vs[3 * vi + 2]);
        if (idx.normal_index < 0) {
          has_n = false;
        } else {
          const size_t ni = static_cast<size_t>(idx.normal_index);
          nrm.emplace_back(ns[3 * ni], ns[3 * ni + 1], ns[3 * ni + 2]);
        }
        if (idx.texcoord_index < 0) {
          has_uv = false;
        } else {
          const size_t ti = static_cast<size_t>(idx.texcoord_index);
          uvs.emplace_back(ts[2 * ti], ts[2 * ti + 1]);
        }
      }
      offset += count;
      const int mat_id = m.material_ids[f];
      const int material = mat_id >= 0 && mat_id < nmat ? mat_id : -1;

      tris.clear();
      if (count == 3) {
        tris = {0, 1, 2};
      } else {
        triangulate_polygon(pos, tris);
      }
      for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        const glm::vec3 p[3] = {pos[tris[t]], pos[tris[t + 1]], pos[tris[t + 2]]};
        glm::vec3 n[3];
        glm::vec2 uv[3];
        for (int k = 0; k < 3; ++k) {
          if (has_n) n[k] = nrm[tris[t + k]];
          if (has_uv) uv[k] = uvs[tris[t + k]];
        }
        add_triangle(mesh, p, has_n ? n : nullptr, has_uv ? uv : nullptr, material);
      }
    }
  }
  return mesh;
}

}  // namespace caustica::mesh_internal
