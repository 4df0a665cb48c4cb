// The environment light on the host (kernels/lib/lights/environment_light.h
// on the device): the scene object's "environment", read into
// Scene::environment; its light-table entry; its image and sampling
// distribution in the device's layout.
//
// Rules: the map is an equirectangular image (.hdr, .exr, .pfm, or an 8-bit
// image decoded from sRGB) or a generated sky (host/scene/sky_model.h),
// times "intensity", turned by "rotate" (degrees, as meshes). It replaces
// "backgroundcolor": a file giving both is an error, as is a missing or
// unreadable map (a stand-in would light the whole scene wrongly), a texel
// that is negative or not finite, or a size beyond host/limits.h. The
// distribution is piecewise constant over texels, f = luminance x sin of
// the row's centre angle, built in double and stored as CDFs (a marginal
// over rows, a conditional per row); with "importance": false, f = sin
// alone (uniform over the sphere: what importance sampling is measured
// against).
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "host/scene/scene.h"

namespace caustica {

namespace scene_detail {
struct LoadContext;
}

// Reads scene_obj's "environment" (when present) into ctx.scene.environment.
void read_environment(scene_detail::LoadContext& ctx, const nlohmann::json& scene_obj);

// Checks an image's texels and size and makes the environment of it;
// `source` names it in messages (throws Error naming it).
Scene::Environment make_environment(const std::string& source, int width, int height, std::vector<float> rgb,
                                    float intensity, const glm::mat3& rotation);

// The `environment` buffer of lib/lights/environment_light.h.
std::vector<float> environment_device_data(const Scene::Environment& env);
std::vector<float> environment_device_data(const Scene& scene);  // one dummy float without an environment

// The light-table entry: the scene's bounding sphere, the map's integral
// of luminance, its largest texel.
Light environment_light(const Scene& scene);

// Integral of luminance over the sphere of directions.
double environment_luminance_integral(const Scene::Environment& env);

}  // namespace caustica
