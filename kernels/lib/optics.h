#line 2 "kernels/lib/optics.h"
/* Mirror reflection, Snell refraction and the exact unpolarised Fresnel
 * reflectance of a dielectric interface. Conventions: d is the unit incident
 * direction (pointing toward the surface), n the unit normal on the side d
 * arrives from (dot(d, n) <= 0), eta = n_incident / n_transmitted. */
#ifndef CAUSTICA_LIB_OPTICS_H
#define CAUSTICA_LIB_OPTICS_H

inline float3 reflect_dir(float3 d, float3 n) { return d - 2.0f * dot(d, n) * n; }

/* Fresnel reflectance for cos_i = -dot(d, n) in [0, 1]. Returns 1 on total
 * internal reflection and the cosine of the transmitted angle in *cos_t. */
inline float fresnel_dielectric(float cos_i, float eta, float* cos_t) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = eta * eta * fmax(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) {
    *cos_t = 0.0f;
    return 1.0f;
  }
  const float ct = sqrt(1.0f - sin2_t);
  *cos_t = ct;
  /* r_s and r_p in the form that stays finite at normal and grazing incidence */
  const float rs = (eta * cos_i - ct) / (eta * cos_i + ct);
  const float rp = (cos_i - eta * ct) / (cos_i + eta * ct);
  return clamp(0.5f * (rs * rs + rp * rp), 0.0f, 1.0f);
}

inline float3 refract_dir(float3 d, float3 n, float eta, float cos_i, float cos_t) {
  return normalize(eta * d + (eta * cos_i - cos_t) * n);
}

#endif
