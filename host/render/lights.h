// What each integrator makes of the scene's lights (Scene keeps them as the
// file writes them).
#pragma once

#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// Phong (Whitted) knows point lights only: the scene's point lights, then one
// stand-in at the centre of every area light and every sphere light, with the
// light's intensity, so that a scene lit only by those is still lit.
std::vector<PointLight> whitted_point_lights(const Scene& scene);

}  // namespace caustica
