#include "host/scene/mesh_tangents.h"

#include <array>
#include <cmath>
#include <cstring>
#include <map>

namespace caustica {

namespace {

// A unit vector perpendicular to unit n (Duff et al. 2017's branchless frame).
glm::vec3 any_perpendicular(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  return glm::vec3(1.0f + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x);
}

// t without its component along unit n, unit; zero when nothing is left.
glm::vec3 perpendicular_part(const glm::vec3& t, const glm::vec3& n) {
  const glm::vec3 p = t - glm::dot(t, n) * n;
  const float l = glm::length(p);
  return l > 1e-20f && std::isfinite(l) ? p / l : glm::vec3(0.0f);
}

// The angle at corner a of triangle (a, b, c).
float corner_angle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 u = b - a, v = c - a;
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

using WeldKey = std::array<uint32_t, 8>;  // the bits of position, normal and uv

WeldKey weld_key(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
  const float values[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
  WeldKey key;
  for (int i = 0; i < 8; ++i) {
    const float v = values[i] == 0.0f ? 0.0f : values[i];  // -0 welds with +0
    std::memcpy(&key[size_t(i)], &v, 4);
  }
  return key;
}

}  // namespace

std::vector<glm::vec4> mikktspace_corner_tangents(const std::vector<glm::vec3>& positions,
                                                  const std::vector<glm::vec3>& normals,
                                                  const std::vector<glm::vec2>& uvs,
                                                  const std::vector<uint32_t>& corners) {
  const size_t triangles = corners.size() / 3;
  std::vector<glm::vec3> corner_normal(corners.size());
  std::vector<glm::vec3> face_tangent(triangles), face_bitangent(triangles);
  std::vector<float> face_sign(triangles, 0.0f);  // 0: degenerate uv
  for (size_t f = 0; f < triangles; ++f) {
    const uint32_t* v = &corners[3 * f];
    const glm::vec3 p0 = positions[v[0]], p1 = positions[v[1]], p2 = positions[v[2]];
    const glm::vec3 face_n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = normals.empty() ? face_n : normals[v[k]];
      const float l = glm::length(n);
      corner_normal[3 * f + size_t(k)] = l > 0.0f && std::isfinite(l) ? n / l : face_n;
    }
    const glm::vec2 d1 = uvs[v[1]] - uvs[v[0]], d2 = uvs[v[2]] - uvs[v[0]];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::fabs(det) > 0.0f) || !std::isfinite(det)) continue;
    const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    face_tangent[f] = (e1 * d2.y - e2 * d1.y) / det;
    face_bitangent[f] = (e2 * d1.x - e1 * d2.x) / det;
    if (!std::isfinite(face_tangent[f].x + face_tangent[f].y + face_tangent[f].z)) continue;
    face_sign[f] = glm::dot(glm::cross(face_n, face_tangent[f]), face_bitangent[f]) < 0.0f ? -1.0f : 1.0f;
  }

  // Sums per welded vertex and handedness.
  std::map<WeldKey, uint32_t> welded;
  std::vector<uint32_t> corner_group(corners.size());
  for (size_t c = 0; c < corners.size(); ++c) {
    const uint32_t v = corners[c];
    const auto it = welded.emplace(weld_key(positions[v], corner_normal[c], uvs[v]), uint32_t(welded.size())).first;
    corner_group[c] = it->second;
  }
  std::vector<glm::vec3> sum(2 * welded.size(), glm::vec3(0.0f));
  for (size_t c = 0; c < corners.size(); ++c) {
    const size_t f = c / 3;
    if (face_sign[f] == 0.0f) continue;
    const uint32_t* v = &corners[3 * f];
    const int k = int(c % 3);
    const float angle = corner_angle(positions[v[k]], positions[v[(k + 1) % 3]], positions[v[(k + 2) % 3]]);
    const glm::vec3 t = perpendicular_part(face_tangent[f], corner_normal[c]);
    if (std::isfinite(angle)) sum[2 * corner_group[c] + (face_sign[f] < 0.0f ? 1 : 0)] += angle * t;
  }

  std::vector<glm::vec4> out(corners.size());
  for (size_t c = 0; c < corners.size(); ++c) {
    const glm::vec3& n = corner_normal[c];
    const float sign = face_sign[c / 3] < 0.0f ? -1.0f : 1.0f;
    glm::vec3 t = perpendicular_part(sum[2 * corner_group[c] + (sign < 0.0f ? 1 : 0)], n);
    if (t == glm::vec3(0.0f)) t = any_perpendicular(n);
    out[c] = glm::vec4(t, sign);
  }
  return out;
}

}  // namespace caustica
