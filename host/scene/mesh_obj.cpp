// Wavefront OBJ through Debian's tinyobjloader (the shared library carries
// the implementation, so TINYOBJLOADER_IMPLEMENTATION must not be defined).
//
// tinyobjloader is asked NOT to triangulate: its built-in ear clipper (2.0
// rc10) can emit triangles outside concave polygons, and only untriangulated
// output still tells how many faces the file had. It also passes
// out-of-range indices through with nothing but a warning, so every index is
// checked here before it is used.
//
// tinyobjloader reads numbers leniently: "nan" or "abc" becomes 0, an index
// of 10^20 goes through atoi (undefined; in practice -1, the last vertex).
// So the text is checked line by line before it is parsed, and every value
// the renderer uses must be a finite number (indices: integers within int32)
// or the load fails naming the file, the line and what was expected. The
// same holds for the material libraries (a "Kd nan" or "Kd -1" would render
// black without a word). Files are read bounded (host/read_file.h).
#include <tiny_obj_loader.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"
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

// The whitespace-separated words of one line (without a trailing comment).
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i < line.size() && line[i] == '#') break;
    const size_t b = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

// A number as a float would hold it; false for text that is not one number
// and for values that are not finite in single precision (nan, inf, 1e39).
bool finite_number(std::string_view w, float* out = nullptr) {
  if (!w.empty() && w[0] == '+') w.remove_prefix(1);
  double d = 0.0;
  const auto r = std::from_chars(w.data(), w.data() + w.size(), d);
  if (r.ec != std::errc() || r.ptr != w.data() + w.size()) return false;
  const float f = static_cast<float>(d);
  if (!std::isfinite(f)) return false;
  if (out) *out = f;
  return true;
}

// Calls fn(line number, words) for every non-empty line of text.
template <class Fn>
void for_each_line(const std::string& text, Fn fn) {
  size_t pos = 0, line = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line;
    const auto w = words(std::string_view(text).substr(pos, end - pos));
    if (!w.empty()) fn(line, w);
    pos = end + 1;
  }
}

std::string quoted(std::string_view w) {
  std::string s(w.substr(0, 40));
  return "'" + s + (w.size() > 40 ? "...'" : "'");
}

// Every number tinyobjloader would read leniently, checked strictly.
void check_obj_text(const std::string& path, const std::string& text) {
  for_each_line(text, [&](size_t line, const std::vector<std::string_view>& w) {
    const std::string where = path + ": line " + std::to_string(line) + ": ";
    const std::string_view key = w[0];
    if (key == "v" || key == "vn" || key == "vt") {
      const char* what = key == "v" ? "vertex coordinate" : key == "vn" ? "normal component" : "texture coordinate";
      const size_t need = key == "vt" ? 1 : 3;
      if (w.size() < need + 1)
        throw Error(where + "expected " + std::to_string(need) + " numbers after '" + std::string(key) + "', got " +
                    std::to_string(w.size() - 1));
      for (size_t i = 1; i < w.size(); ++i)
        if (!finite_number(w[i]))
          throw Error(where + "expected a finite " + what + " (a number within single precision), got " + quoted(w[i]));
    } else if (key == "f") {
      for (size_t i = 1; i < w.size(); ++i) {
        std::string_view rest = w[i];
        while (true) {
          const size_t slash = rest.find('/');
          const std::string_view part = rest.substr(0, slash);
          if (!part.empty()) {
            int64_t v = 0;
            const auto r = std::from_chars(part.data(), part.data() + part.size(), v);
            if (r.ec != std::errc() || r.ptr != part.data() + part.size() || v == 0 || v > INT32_MAX ||
                v < -int64_t(INT32_MAX))
              throw Error(where + "expected face indices (non-zero integers within +-2147483647, as v, v/vt, v//vn "
                                  "or v/vt/vn), got " + quoted(w[i]));
          }
          if (slash == std::string_view::npos) break;
          rest.remove_prefix(slash + 1);
        }
      }
    }
  });
}

// Colours must be finite and non-negative, exponents and indices finite and
// non-negative: anything else would shade black or NaN without a word.
// Reflectances (Ka, Kd, Ks, Tf) are at most limits::kMaxReflectance, as in
// scene files; emission (Ke) is not bounded.
void check_mtl_text(const std::string& name, const std::string& text) {
  for_each_line(text, [&](size_t line, const std::vector<std::string_view>& w) {
    const std::string_view key = w[0];
    const bool colour = key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "Tf";
    const bool scalar = key == "Ns" || key == "Ni" || key == "d" || key == "Tr";
    if (!colour && !scalar) return;
    if (colour && w.size() > 1 && (w[1] == "spectral" || w[1] == "xyz")) return;  // not read by tinyobjloader
    const std::string where = name + ": line " + std::to_string(line) + ": " + std::string(key) + ": ";
    const std::string what = colour ? "1 or 3 finite non-negative numbers" : "a finite non-negative number";
    std::string got;
    for (size_t i = 1; i < w.size(); ++i) got += (i > 1 ? " " : "") + std::string(w[i].substr(0, 40));
    if (colour ? (w.size() != 2 && w.size() != 4) : w.size() != 2)
      throw Error(where + "expected " + what + ", got '" + got + "'");
    const bool reflectance = colour && key != "Ke";
    for (size_t i = 1; i < w.size(); ++i) {
      float v = 0.0f;
      if (!finite_number(w[i], &v) || v < 0.0f) throw Error(where + "expected " + what + ", got '" + got + "'");
      if (reflectance && v > limits::kMaxReflectance)
        throw Error(where + "expected a reflectance in [0, " + std::to_string(int(limits::kMaxReflectance)) +
                    "] (1 reflects all the light that arrives), got '" + got + "'");
    }
  });
}

// Reads "mtllib" files through `source`, checks them, then lets
// tinyobjloader parse them; a missing one is the same warning as
// tinyobjloader's own (collect_warnings rewords it).
class CheckedMaterialReader : public tinyobj::MaterialReader {
 public:
  explicit CheckedMaterialReader(const MtlSource& source) : source_(source) {}
  bool operator()(const std::string& id, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* map, std::string* warn, std::string* err) override {
    std::string text, name, missing;
    if (!source_(id, text, name, missing)) {
      if (warn) *warn += missing + "\n";
      return false;
    }
    check_mtl_text(name, text);
    std::istringstream in(text);
    tinyobj::LoadMtl(map, materials, &in, warn, err);
    return true;
  }

 private:
  const MtlSource& source_;
};

}  // namespace

Mesh load_obj(const std::string& path) {
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const MtlSource files = [&dir](const std::string& id, std::string& text, std::string& name, std::string& missing) {
    name = dir.empty() ? id : (std::filesystem::path(dir) / id).string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(name, ec)) {
      missing = "Material file [ " + id + " ] not found in a path : " + dir;
      return false;
    }
    text = read_input_file(name, "material library", limits::kMaxMaterialFileBytes);
    return true;
  };
  return parse_obj(path, read_input_file(path, "OBJ file", limits::kMaxMeshFileBytes), files);
}

Mesh parse_obj(const std::string& path, const std::string& text, const MtlSource& mtl) {
  check_obj_text(path, text);
  tinyobj::attrib_t attrib_storage;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;
  {
    std::istringstream in(text);
    CheckedMaterialReader reader(mtl);
    if (!tinyobj::LoadObj(&attrib_storage, &shapes, &materials, &warnings, &errors, &in, &reader,
                          /*triangulate=*/false, /*default_vcols_fallback=*/false)) {
      std::string msg = trim(errors);
      throw Error(path + ": cannot read OBJ file" + (msg.empty() ? "" : ": " + msg));
    }
  }

  Mesh mesh;
  collect_warnings(path, warnings, mesh);
  // tinyobjloader collects MTL errors (it has none in practice) next to parse
  // errors without failing; they are only worth a warning.
  if (const std::string err = trim(errors); !err.empty()) mesh.warnings.push_back(path + ": " + err);

  const std::string obj_dir = std::filesystem::path(path).parent_path().string();
  for (const auto& m : materials) {
    MeshMaterial mm;
    mm.name = m.name;
    mm.kd = glm::vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    mm.ks = glm::vec3(m.specular[0], m.specular[1], m.specular[2]);
    mm.ke = glm::vec3(m.emission[0], m.emission[1], m.emission[2]);
    mm.ns = m.shininess;
    mm.diffuse_texture = resolve_texture(obj_dir, m.diffuse_texname);
    mesh.materials.push_back(std::move(mm));
  }

  const tinyobj::attrib_t& attrib = attrib_storage;
  const auto& vs = attrib.vertices;
  const auto& ns = attrib.normals;
  const auto& ts = attrib.texcoords;
  const long long nv = static_cast<long long>(vs.size() / 3);
  const long long nn = static_cast<long long>(ns.size() / 3);
  const long long nt = static_cast<long long>(ts.size() / 2);
  const int nmat = static_cast<int>(mesh.materials.size());

  size_t total_faces = 0;
  for (const auto& shape : shapes) total_faces += shape.mesh.num_face_vertices.size();
  mesh.source_faces += total_faces;
  mesh.triangles.reserve(total_faces + total_faces / 8);

  std::vector<glm::vec3> pos, nrm;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> tris;
  size_t face_number = 0;  // 1-based, over the whole file, for messages
  for (const auto& shape : shapes) {
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
