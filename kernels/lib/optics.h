#line 2 "kernels/lib/optics.h"
/* Mirror reflection, Snell refraction and the exact unpolarised Fresnel
 * reflectance of a dielectric interface. Conventions: d is the unit incident
 * direction (pointing toward the surface), n the unit normal on the side d
 * arrives from (dot(d, n) <= 0), eta = n_incident / n_transmitted. */
#ifndef CAUSTICA_LIB_OPTICS_H
#define CAUSTICA_LIB_OPTICS_H

#include "shared/compat.h"

inline float3 reflect_dir(float3 d, float3 n) { return d - 2.0f * dot(d, n) * n; }

/* Fresnel reflectance for cos_i = -dot(d, n) in [0, 1]. Returns 1 on total
 * internal reflection and the cosine of the transmitted angle in *cos_t. */
inline float fresnel_dielectric(float cos_i, float eta, float* cos_t) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  /* cos^2 t = 1 - eta^2 (1 - cos^2 i), summed as (1 - eta^2) + (eta cos_i)^2:
   * for eta = 1 that is exactly 0 + cos_i^2, so matched media give
   * cos_t == cos_i and no reflection even at grazing incidence (1 - (1 - c^2)
   * loses c^2 below float resolution and reported total reflection there).
   * The sum can round a hair above 1 (eta != 1, cos_i near 1): clamped. */
  const float a = eta * cos_i;
  const float cos2_t = (1.0f - eta * eta) + a * a;
  if (cos2_t <= 0.0f) {
    *cos_t = 0.0f;
    return 1.0f;
  }
  const float ct = sqrt(fmin(cos2_t, 1.0f));
  *cos_t = ct;
  /* r_s and r_p in the form that stays finite at normal and grazing incidence */
  const float rs = (a - ct) / (a + ct);
  const float rp = (cos_i - eta * ct) / (cos_i + eta * ct);
  return clamp(0.5f * (rs * rs + rp * rp), 0.0f, 1.0f);
}

inline float3 refract_dir(float3 d, float3 n, float eta, float cos_i, float cos_t) {
  return normalize(eta * d + (eta * cos_i - cos_t) * n);
}

/* Unit shading normal n moved, if it must be, so that the reflection of
 * the unit view direction wo about it rises at least q = min(0.9 cos_g,
 * 0.01) above the geometric surface of unit normal ng (n, ng on wo's side;
 * cos_g = wo . ng): Cycles' condition, with the half vector of wo and the
 * reflection lifted to exactly q (its azimuth kept) as the new normal
 * (lib/normal_map.h says why). */
inline float3 normal_with_valid_reflection(float3 n, float3 ng, float3 wo) {
  const float cos_g = dot(wo, ng);
  const float q = fmin(0.9f * cos_g, 0.01f);
  const float3 r = 2.0f * dot(wo, n) * n - wo;
  const float rise = dot(r, ng);
  if (rise >= q) return n;
  /* R's direction along the surface (the view's mirror image where R has none). */
  float3 along = r - rise * ng;
  float len2 = dot(along, along);
  if (!(len2 > 1e-12f)) {
    along = dot(wo, ng) * ng - wo;
    len2 = dot(along, along);
    if (!(len2 > 1e-12f)) return ng;
  }
  const float3 lifted = along * (sqrt(fmax(1.0f - q * q, 0.0f)) * rsqrt(len2)) + q * ng;
  const float3 h = wo + lifted;
  const float hl2 = dot(h, h);
  return hl2 > 1e-12f ? h * rsqrt(hl2) : ng;
}

#endif
