// Triangle meshes from files: Wavefront OBJ (through Debian's tinyobjloader)
// and Stanford PLY (ASCII, binary little- and big-endian). The result is a
// flat triangle soup in the file's own coordinates; the scene loader applies
// the shape's transform and material. Degenerate and zero-area triangles are
// dropped and counted, never passed on.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace caustica {

struct MeshMaterial {
  std::string name;
  glm::vec3 kd{0.8f};
  glm::vec3 ks{0.0f};
  glm::vec3 ke{0.0f};
  float ns = 10.0f;
  std::string diffuse_texture;  // map_Kd as written in the MTL (resolve against the mesh's folder)
};

struct MeshTriangle {
  glm::vec3 p[3];
  glm::vec3 n[3];   // unit vertex normals when has_normals
  glm::vec2 uv[3];  // when has_uvs
  // glTF only: tangents (xyz, w the bitangent sign) for a normal-mapped
  // material, and COLOR_0 (linear rgba).
  glm::vec4 tangent[3];  // when has_tangents
  glm::vec4 colour[3];   // when has_colours
  bool has_normals = false;
  bool has_uvs = false;
  bool has_tangents = false;
  bool has_colours = false;
  int material = -1;  // index into Mesh::materials, -1: none
};

struct Mesh {
  std::vector<MeshTriangle> triangles;
  std::vector<MeshMaterial> materials;
  size_t source_faces = 0;        // faces in the file (before triangulation)
  size_t dropped_degenerate = 0;  // zero-area or non-finite triangles removed
  std::vector<std::string> warnings;  // e.g. a missing MTL file
};

// By extension (.obj / .ply, case-insensitive). Throws caustica::Error naming
// the file (and the line or element for syntax errors) on unreadable input.
Mesh load_mesh(const std::string& path);

}  // namespace caustica
