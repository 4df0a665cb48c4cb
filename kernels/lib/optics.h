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

#endif
