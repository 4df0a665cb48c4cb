// Triangle light (kernels/lib/lights/triangle_light.h): every emissive
// triangle of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

namespace {

// The tree: its corners, emitting on the side of cross(p1 - p0, p2 - p0)
// (both with LIGHT_TWO_SIDED); an emission texture's mean is in the power.
LightBounds triangle_tree_bounds(const Light& l) {
  const glm::vec3 corners[3] = {to_vec3(l.p0), to_vec3(l.p1), to_vec3(l.p2)};
  return planar_bounds(corners, 3, glm::cross(corners[1] - corners[0], corners[2] - corners[0]),
                       (l.flags & LIGHT_TWO_SIDED) != 0u);
}

}  // namespace

LightType triangle_light_type() {
  LightType t = shape_light_type(LIGHT_TRIANGLE);
  t.tree_bounds = triangle_tree_bounds;
  return t;
}

}  // namespace caustica
