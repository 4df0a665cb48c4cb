// Format dispatch plus the parts every mesh format shares: the filter that
// keeps unusable triangles away from the renderer, and polygon triangulation.
#include "host/scene/mesh.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <system_error>

#include "host/error.h"
#include "host/scene/mesh_internal.h"

namespace caustica {
namespace mesh_internal {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Exact-zero checks are not enough: a sliver whose edges are parallel to
// within rounding has a meaningless geometric normal and wastes BVH nodes.
constexpr double kMinRelativeArea = 1e-12;

bool usable_area(const glm::vec3 (&p)[3]) {
  for (const auto& v : p)
    if (!finite(v)) return false;
  // The renderer builds the geometric normal in float; if that comes out
  // zero or overflows, the hit would shade with NaNs whatever double says.
  const glm::vec3 cf = glm::cross(p[1] - p[0], p[2] - p[0]);
  if (!finite(cf) || (cf.x == 0.0f && cf.y == 0.0f && cf.z == 0.0f)) return false;
  const glm::dvec3 a(p[0]), b(p[1]), c(p[2]);
  const glm::dvec3 e0 = b - a, e1 = c - a, e2 = c - b;
  const double longest2 = std::max({glm::dot(e0, e0), glm::dot(e1, e1), glm::dot(e2, e2)});
  return glm::length(glm::cross(e0, e1)) > kMinRelativeArea * longest2;
}

bool unit_normals(const glm::vec3* n, glm::vec3 (&out)[3]) {
  for (int k = 0; k < 3; ++k) {
    if (!finite(n[k])) return false;
    const glm::dvec3 d(n[k]);
    const double len = glm::length(d);
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    out[k] = glm::vec3(d / len);
    if (!finite(out[k])) return false;
  }
  return true;
}

double cross2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

}  // namespace

void add_triangle(Mesh& mesh, const glm::vec3 (&p)[3], const glm::vec3* n, const glm::vec2* uv,
                  int material, const glm::vec4* tangents, const glm::vec4* colours) {
  if (!usable_area(p)) {
    ++mesh.dropped_degenerate;
    return;
  }
  MeshTriangle t;
  for (int k = 0; k < 3; ++k) t.p[k] = p[k];
  t.has_normals = n && unit_normals(n, t.n);
  if (!t.has_normals)
    for (auto& v : t.n) v = glm::vec3(0.0f);
  if (uv) {
    t.has_uvs = true;
    for (int k = 0; k < 3; ++k) {
      t.uv[k] = uv[k];
      t.has_uvs = t.has_uvs && std::isfinite(uv[k].x) && std::isfinite(uv[k].y);
    }
  }
  if (!t.has_uvs)
    for (auto& v : t.uv) v = glm::vec2(0.0f);
  // A tangent that the world transform squashed to nothing costs the
  // triangle its normal map (the kernel reads a zero tangent as none).
  t.has_tangents = tangents != nullptr;
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 d = tangents ? glm::vec3(tangents[k]) : glm::vec3(0.0f);
    const float l = glm::length(d);
    t.tangent[k] = l > 0.0f && std::isfinite(l) ? glm::vec4(d / l, tangents[k].w < 0.0f ? -1.0f : 1.0f)
                                                 : glm::vec4(0.0f);
  }
  t.has_colours = colours != nullptr;
  for (int k = 0; k < 3; ++k) t.colour[k] = colours ? colours[k] : glm::vec4(1.0f);
  t.material = material;
  mesh.triangles.push_back(t);
}

void triangulate_polygon(const std::vector<glm::vec3>& corners, std::vector<uint32_t>& out) {
  const size_t n = corners.size();
  std::vector<uint32_t> rem(n);
  std::iota(rem.begin(), rem.end(), 0u);
  auto fan = [&out](const std::vector<uint32_t>& idx) {
    for (size_t k = 1; k + 1 < idx.size(); ++k) out.insert(out.end(), {idx[0], idx[k], idx[k + 1]});
  };

  // Newell's normal is robust for non-planar and partly collinear polygons;
  // its dominant axis picks the projection plane with the least distortion.
  glm::dvec3 nn(0.0);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 a(corners[i]), b(corners[(i + 1) % n]);
    nn.x += (a.y - b.y) * (a.z + b.z);
    nn.y += (a.z - b.z) * (a.x + b.x);
    nn.z += (a.x - b.x) * (a.y + b.y);
  }
  const glm::dvec3 an = glm::abs(nn);
  if (!std::isfinite(an.x + an.y + an.z) || an.x + an.y + an.z == 0.0) {
    fan(rem);  // no plane to clip in; the degenerate pieces get dropped later
    return;
  }
  const int axis = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  int u = (axis + 1) % 3, v = (axis + 2) % 3;
  if (nn[axis] < 0.0) std::swap(u, v);  // makes the projected polygon counter-clockwise
  std::vector<glm::dvec2> q(n);
  for (size_t i = 0; i < n; ++i) q[i] = glm::dvec2(corners[i][u], corners[i][v]);

  // Trying corner 1 first and staying there after each clip reproduces the
  // fan from corner 0 for convex polygons, the split most files expect.
  size_t j = 1, misses = 0;
  while (rem.size() > 3) {
    const size_t m = rem.size();
    j %= m;
    const uint32_t a = rem[(j + m - 1) % m], b = rem[j], c = rem[(j + 1) % m];
    bool ear = cross2(q[a], q[b], q[c]) > 0.0;
    for (size_t k = 0; ear && k < m; ++k) {
      const uint32_t o = rem[k];
      if (o == a || o == b || o == c || q[o] == q[a] || q[o] == q[b] || q[o] == q[c]) continue;
      if (cross2(q[a], q[b], q[o]) >= 0.0 && cross2(q[b], q[c], q[o]) >= 0.0 && cross2(q[c], q[a], q[o]) >= 0.0)
        ear = false;
    }
    if (ear) {
      out.insert(out.end(), {a, b, c});
      rem.erase(rem.begin() + static_cast<std::ptrdiff_t>(j));
      misses = 0;
    } else {
      ++j;
      if (++misses >= m) break;  // self-intersecting: no ear left, fan the rest
    }
  }
  fan(rem);
}

}  // namespace mesh_internal

Mesh load_mesh(const std::string& path) {
  namespace fs = std::filesystem;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply")
    throw Error(path + ": unsupported mesh format '" + ext + "' (expected .obj or .ply)");

  // Checked here because tinyobjloader's own message for a directory or a
  // missing file is an empty mesh or a terse "Cannot open".
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(path + ": mesh file does not exist");
  if (!fs::is_regular_file(status)) throw Error(path + ": mesh path is not a regular file");

  Mesh mesh = ext == ".obj" ? mesh_internal::load_obj(path) : mesh_internal::load_ply(path);
  if (mesh.triangles.empty())
    mesh.warnings.push_back(path + ": no usable triangles (" + std::to_string(mesh.source_faces) + " faces, " +
                            std::to_string(mesh.dropped_degenerate) + " degenerate triangles dropped)");
  return mesh;
}

}  // namespace caustica
