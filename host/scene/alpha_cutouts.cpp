#include "host/scene/alpha_cutouts.h"

namespace caustica {

std::vector<TriangleAlpha> triangle_alpha(const Scene& scene) {
  std::vector<TriangleAlpha> out(scene.triangles.size());
  const bool shaded = scene.triangle_shading.size() == scene.triangles.size();
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const Material& m = scene.materials[scene.triangles[i].material];
    TriangleAlpha& a = out[i];
    if (m.flags & MATERIAL_ALPHA_MASK) a.mode = ALPHA_MASK;
    else if (m.flags & MATERIAL_ALPHA_BLEND) a.mode = ALPHA_BLEND;
    else continue;
    a.factor = m.alpha_factor;
    a.cutoff = m.alpha_cutoff;
    a.offset = ALPHA_NO_IMAGE;
    if (m.texture < 0 || scene.textures[size_t(m.texture)].kind != TEXTURE_IMAGE) continue;
    const Texture& tex = scene.textures[size_t(m.texture)];
    a.offset = tex.offset;
    a.width = tex.width;
    a.height = tex.height;
    a.sampling = tex.sampling & ~TEXTURE_TRANSFORMED;
    // The default corners are those of a triangle without shading data
    // (kernels/lib/surface.h: triangle_uv).
    glm::vec2 uv[3] = {{0, 0}, {1, 0}, {0, 1}};
    if (shaded) {
      const TriangleShading& s = scene.triangle_shading[i];
      uv[0] = {s.u0, s.v0};
      uv[1] = {s.u1, s.v1};
      uv[2] = {s.u2, s.v2};
    }
    if (tex.sampling & TEXTURE_TRANSFORMED)
      for (glm::vec2& c : uv)
        c = glm::vec2(tex.uv_u.x * c.x + tex.uv_u.y * c.y + tex.uv_u.z, tex.uv_v.x * c.x + tex.uv_v.y * c.y + tex.uv_v.z);
    a.u0 = uv[0].x, a.v0 = uv[0].y;
    a.u1 = uv[1].x, a.v1 = uv[1].y;
    a.u2 = uv[2].x, a.v2 = uv[2].y;
  }
  return out;
}

}  // namespace caustica
