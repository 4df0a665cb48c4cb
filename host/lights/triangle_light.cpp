// Triangle light (kernels/lib/lights/triangle_light.h): every emissive
// triangle of the scene (light_table.cpp makes them from the shapes and
// their materials); no file form, no phong stand-in.
#include "host/lights/light_types.h"

namespace caustica {

LightType triangle_light_type() { return shape_light_type(LIGHT_TRIANGLE); }

}  // namespace caustica
