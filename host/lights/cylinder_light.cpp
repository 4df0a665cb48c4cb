// Cylinder light (kernels/lib/lights/cylinder_light.h): every emissive
// cylinder of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

LightType cylinder_light_type() { return shape_light_type(LIGHT_CYLINDER); }

}  // namespace caustica
