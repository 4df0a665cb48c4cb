// Tangents for normal maps where a glTF primitive gives none (its TANGENT
// attribute), computed as the glTF specification asks: by MikkTSpace's
// rules (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited", MSc
// thesis, University of Copenhagen; its reference code, mikktspace.c, is in
// Blender and Unreal but not packaged by Debian), so that a normal map baked
// against MikkTSpace tangents reads back the normals it was baked from.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace caustica {

// One tangent per corner (corners: three vertex indices per triangle), xyz
// unit and perpendicular to the corner's normal, w the bitangent sign
// (+1 or -1: the bitangent is w cross(N, T)). `normals` may be empty (flat
// triangles, as glTF asks for a primitive without NORMAL); `uvs` are this
// renderer's texture coordinates (v up the image). The steps:
//  1. each triangle's tangent and bitangent: the derivatives of position
//     along u and v, from its edges e1 = du1 T + dv1 B, e2 = du2 T + dv2 B;
//  2. vertices are welded where position, normal and uv are all equal
//     (MikkTSpace works on values, not index buffers);
//  3. at each welded vertex, the tangents of the triangles sharing it are
//     projected onto the normal's plane, normalised, weighted by the
//     triangle's angle at that corner and summed, separately for the two
//     handednesses (sign of cross(N, T) . B): a mirrored uv seam keeps its
//     two frames, as MikkTSpace splits such a vertex;
//  4. each corner reads the sum of its own handedness, made perpendicular
//     to its normal (Gram-Schmidt) and unit.
// A corner whose triangles all have degenerate texture coordinates (zero
// uv area) gets an arbitrary unit tangent perpendicular to its normal and
// w = 1, as MikkTSpace does. Not reproduced: MikkTSpace also splits a
// welded vertex between triangles whose tangents differ by more than a
// threshold angle ("non-smooth" groups); here such tangents are averaged.
std::vector<glm::vec4> mikktspace_corner_tangents(const std::vector<glm::vec3>& positions,
                                                  const std::vector<glm::vec3>& normals,
                                                  const std::vector<glm::vec2>& uvs,
                                                  const std::vector<uint32_t>& corners);

}  // namespace caustica
