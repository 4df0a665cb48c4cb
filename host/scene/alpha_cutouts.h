// The triangles' alpha cut-outs as the traversal reads them
// (TriangleAlpha, kernels/shared/types.h; kernels/lib/alpha_cutout.h):
// made from each triangle's material (MATERIAL_ALPHA_MASK / _BLEND, its
// alpha factor and cut-off, the alpha channel of its base colour texture)
// and texture coordinates, with the texture's KHR_texture_transform
// applied to the corners.
#pragma once

#include <vector>

#include "host/scene/scene.h"

namespace caustica {

// One record per scene triangle; ALPHA_OPAQUE for triangles whose material
// has neither mode.
std::vector<TriangleAlpha> triangle_alpha(const Scene& scene);

}  // namespace caustica
