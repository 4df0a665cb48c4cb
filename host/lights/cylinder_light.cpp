// Cylinder light (kernels/lib/lights/cylinder_light.h): every emissive
// cylinder of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

LightType cylinder_light_type() {
  LightType t;
  t.kind = LIGHT_CYLINDER;
  t.power = area_light_power;
  return t;
}

}  // namespace caustica
