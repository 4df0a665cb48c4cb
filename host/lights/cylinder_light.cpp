// Cylinder light (kernels/lib/lights/cylinder_light.h): every emissive
// cylinder of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

namespace {

// The tree: the box of its side and caps (per axis, the half length along
// the axis plus the radius across it), emitting every way.
LightBounds cylinder_tree_bounds(const Light& l) {
  const glm::vec3 c = to_vec3(l.p0), axis = to_vec3(l.p1);
  const float radius = l.p0.w, half = l.p1.w;
  const glm::vec3 across = radius * glm::sqrt(glm::max(glm::vec3(0.0f), 1.0f - axis * axis));
  const glm::vec3 extent = glm::abs(axis) * half + across;
  return omnidirectional_bounds(c - extent, c + extent);
}

}  // namespace

LightType cylinder_light_type() {
  LightType t = shape_light_type(LIGHT_CYLINDER);
  t.tree_bounds = cylinder_tree_bounds;
  return t;
}

}  // namespace caustica
