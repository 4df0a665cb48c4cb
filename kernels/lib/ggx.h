#line 2 "kernels/lib/ggx.h"
/* The GGX (Trowbridge-Reitz) microfacet distribution with Smith's
 * height-correlated masking-shadowing, and sampling of its visible normals.
 *
 * Rules: directions are unit vectors in the local frame of the macro
 * surface (z = normal, sampling.h's frame_from_normal); alpha is the
 * isotropic roughness. The functions are meant for alpha >= GGX_ALPHA_MIN:
 * below it the lobe is narrower than float directions resolve and the
 * caller must treat the surface as perfectly smooth (mirror / smooth
 * dielectric), which is what the microfacet model converges to. */
#ifndef CAUSTICA_LIB_GGX_H
#define CAUSTICA_LIB_GGX_H

#include "shared/compat.h"

#define GGX_ALPHA_MIN 1e-3f

/* D(m): density of micro-normals per unit solid angle times cos(theta_m)
 * normalisation (integral of D(m) m.z over the hemisphere = 1). sin^2 is
 * taken from the components, not as 1 - cos^2: near the pole (where a small
 * alpha puts every micro-normal) 1 - m.z^2 keeps only a few bits, which at
 * alpha = GGX_ALPHA_MIN made D wrong by several percent per evaluation. */
inline float ggx_d(float3 m, float alpha) {
  if (m.z <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  const float t = a2 * m.z * m.z + (m.x * m.x + m.y * m.y); /* a^2 cos^2 + sin^2 */
  return a2 / (M_PI_F * t * t);
}

/* Smith's Lambda(w) for GGX, written with tan^2 from the components so that
 * it stays finite at grazing angles. */
inline float ggx_lambda(float3 w, float alpha) {
  const float c2 = w.z * w.z;
  const float s2 = fmax(0.0f, w.x * w.x + w.y * w.y);
  if (c2 <= 0.0f) return 1e30f; /* tangent: fully masked */
  const float a2_tan2 = alpha * alpha * s2 / c2;
  return 0.5f * (sqrt(1.0f + a2_tan2) - 1.0f);
}

inline float ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + ggx_lambda(w, alpha)); }

/* Height-correlated masking-shadowing of the pair (wo, wi). */
inline float ggx_g2(float3 wo, float3 wi, float alpha) {
  return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/* A micro-normal m distributed as the normals visible from wo (wo.z > 0):
 * density D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z, sampled exactly by
 * Dupuy & Benyoub's spherical caps (2023): stretch wo into the hemisphere
 * configuration, sample the spherical cap of directions it sees, unstretch. */
inline float3 ggx_sample_visible_normal(float3 wo, float alpha, float2 u) {
  const float3 wh = normalize(make_float3(alpha * wo.x, alpha * wo.y, wo.z));
  float cos_phi;
  const float sin_phi = sincos(2.0f * M_PI_F * u.x, &cos_phi);
  const float z = fma(1.0f - u.y, 1.0f + wh.z, -wh.z);
  const float sin_theta = sqrt(clamp(1.0f - z * z, 0.0f, 1.0f));
  const float3 c = make_float3(sin_theta * cos_phi, sin_theta * sin_phi, z);
  const float3 h = c + wh;
  return normalize(make_float3(alpha * h.x, alpha * h.y, fmax(h.z, 0.0f)));
}

/* Density of ggx_sample_visible_normal, per unit solid angle of m. */
inline float ggx_pdf_visible_normal(float3 wo, float3 m, float alpha) {
  if (wo.z <= 0.0f) return 0.0f;
  return ggx_g1(wo, alpha) * fmax(0.0f, dot(wo, m)) * ggx_d(m, alpha) / wo.z;
}

#endif /* CAUSTICA_LIB_GGX_H */
