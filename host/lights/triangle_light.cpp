// Triangle light (kernels/lib/lights/triangle_light.h): every emissive
// triangle of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

LightType triangle_light_type() {
  LightType t;
  t.kind = LIGHT_TRIANGLE;
  t.power = area_light_power;
  return t;
}

}  // namespace caustica
