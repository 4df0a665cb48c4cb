// Private to the mesh loaders (mesh.cpp, mesh_obj.cpp, mesh_ply.cpp): the
// per-format readers differ only in how they decode faces, so the checks that
// decide what reaches the renderer (degenerate triangles, bad normals) and the
// polygon triangulation live in one place and behave the same for OBJ and PLY.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host/scene/mesh.h"

namespace caustica::mesh_internal {

// Appends one triangle to mesh, or counts it in mesh.dropped_degenerate when
// it has no usable area or a non-finite corner. n / uv point at three corner
// values, or are null when the face has none; normals need not be unit length
// (bad ones only cost the triangle its shading normals). glTF primitives
// may also give tangents (xyz, w the bitangent sign) and vertex colours.
void add_triangle(Mesh& mesh, const glm::vec3 (&p)[3], const glm::vec3* n, const glm::vec2* uv,
                  int material, const glm::vec4* tangents = nullptr, const glm::vec4* colours = nullptr);

// Splits a polygon with corners.size() >= 4 into triangles, appending corner
// positions (indices into corners) three at a time to out. Convex polygons
// become a fan from corner 0; concave ones are ear-clipped in their best-fit
// plane, so no triangle covers the outside of the polygon.
void triangulate_polygon(const std::vector<glm::vec3>& corners, std::vector<uint32_t>& out);

Mesh load_obj(const std::string& path);
Mesh load_ply(const std::string& path);

// The parsers behind them, from bytes already read (the fuzz targets in
// fuzz/ call these). `path` only names the file in messages.
// An OBJ's material libraries come from `mtl`: given the name an "mtllib"
// line writes, it fills in the text and the name for messages and returns
// true, or fills in a warning and returns false when there is none.
using MtlSource = std::function<bool(const std::string& mtllib, std::string& text, std::string& name,
                                     std::string& missing_warning)>;
Mesh parse_obj(const std::string& path, const std::string& text, const MtlSource& mtl);
Mesh parse_ply(const std::string& path, std::string data);

}  // namespace caustica::mesh_internal
