#line 2 "kernels/lib/bsdf.h"
/* The scattering models of the path tracer (issue 11), evaluated, sampled
 * and given densities in one place so that the three always agree.
 *
 * Rules: directions are unit vectors in the local shading frame (z = the
 * shading normal on the side the path arrived from is NOT assumed: wo.z may
 * be negative inside a dielectric). wo points away from the surface toward
 * where the path came from, wi away from the surface toward where it goes.
 * bsdf_eval returns f(wo, wi) without the cosine; bsdf_sample returns the
 * sampled wi with weight = f |wi.z| / pdf (or the delta lobe's weight), and
 * flags BSDF_SAMPLED_SPECULAR for delta lobes, whose pdf is not a density
 * (MIS must not weight them). Radiance transport: transmission divides by
 * eta^2 (the non-symmetric scaling of camera paths, Veach 1997 ch. 5).
 * Near-zero roughness (alpha < GGX_ALPHA_MIN) is the smooth model.
 *
 * Models:
 *   BSDF_PLASTIC: Lambertian albedo `diffuse` coupled with a GGX specular
 *     layer (a mirror when smooth) of normal reflectance `specular` (Schlick
 *     Fresnel) by Ashikhmin & Shirley's energy-conserving diffuse term
 *     (2000), so the total reflectance stays <= 1 when diffuse and specular
 *     are <= 1 per channel. Without a layer (specular = 0) it is exactly
 *     Lambertian: albedo `diffuse` at every angle;
 *   BSDF_CONDUCTOR: GGX (or smooth mirror) with Schlick reflectance
 *     `specular`;
 *   BSDF_DIELECTRIC: smooth or rough (Walter et al. 2007) glass of relative
 *     index `ior` (inside over outside; the outside is where z > 0), its
 *     transmission tinted by `diffuse` (white for clear glass; glTF's base
 *     colour for KHR_materials_transmission).
 * Plastic and conductor may carry a clear coat (HAS_CLEARCOAT; below). */
#ifndef CAUSTICA_LIB_BSDF_H
#define CAUSTICA_LIB_BSDF_H

#include "lib/ggx.h"
#include "lib/optics.h"
#include "lib/sampling.h"

/* Programs without glass leave the dielectric out (#if HAS_DIELECTRIC,
 * shared/feature_flags.h). */

#define BSDF_PLASTIC 0u
#define BSDF_CONDUCTOR 1u
#define BSDF_DIELECTRIC 2u

#define BSDF_SAMPLED_SPECULAR 1u  /* a delta lobe: pdf is not a density */
#define BSDF_SAMPLED_TRANSMIT 2u  /* wi is on the other side of the surface */

typedef struct {
  float3 diffuse;  /* plastic: Lambertian albedo; dielectric: the transmission's tint (glTF's base colour) */
  float3 specular; /* plastic, conductor: reflectance at normal incidence */
  float alpha;     /* GGX roughness */
  float ior;       /* dielectric: inside / outside */
  uint kind;
  /* A clear coat over a plastic or conductor (glTF's KHR_materials_clearcoat;
   * read only with HAS_CLEARCOAT): its weight c in [0, 1] (0: none) and
   * GGX roughness. */
  float coat;
  float coat_alpha;
  float3 coat_n; /* the coat's normal in this local frame ((0, 0, 1): the shading normal) */
} Bsdf;

inline float bsdf_max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

inline float3 fresnel_schlick(float3 f0, float cos_theta) {
  const float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (1.0f - f0) * (m2 * m2 * m);
}

/* Matched media: glass of IOR 1 refracts every micro-normal's ray straight
 * on with no reflection, so its rough model is the straight line too, a
 * delta that Walter's half vector (wo + wi = 0) cannot express (it gave
 * NaN): it is the smooth model whatever its roughness. */
inline bool bsdf_is_smooth(Bsdf b) { return b.alpha < GGX_ALPHA_MIN || (b.kind == BSDF_DIELECTRIC && b.ior == 1.0f); }

/* The local frame in which a path (or a photon) arriving along d scatters:
 * opaque surfaces are two-sided, so their frame turns toward d; dielectrics
 * keep the outward normal (the side tells inside from outside); a shading
 * normal beyond the geometric surface gives way to the geometric normal (no
 * light leaks through interpolated normals). ng: the geometric normal, turned
 * as n. */
typedef struct {
  float3 t, b, n, ng;
} ShadingFrame;

inline ShadingFrame shading_frame(Bsdf bsdf, float3 shading_normal, float3 normal, float3 d) {
  ShadingFrame f;
  const bool opaque = bsdf.kind != BSDF_DIELECTRIC;
  f.n = shading_normal;
  f.ng = normal;
  if (opaque && dot(f.ng, d) > 0.0f) {
    f.n = -f.n;
    f.ng = -f.ng;
  }
  if (opaque && dot(f.n, f.ng) < 0.0f) f.n = f.ng;
  frame_from_normal(f.n, &f.t, &f.b);
  return f;
}

/* Probability that plastic sampling picks the specular lobe: proportional
 * to the lobes' reflectance scales, never 0 or 1 while both exist. */
inline float plastic_specular_probability(Bsdf b) {
  const float s = bsdf_max3(b.specular), d = bsdf_max3(b.diffuse);
  if (s <= 0.0f) return 0.0f;
  if (d <= 0.0f) return 1.0f;
  return clamp(s / (s + d), 0.1f, 0.9f);
}

/* The microfacet reflection term D G F / (4 |cos_o| |cos_i|) for wo, wi on
 * the +z side. */
inline float3 ggx_reflection(float3 f0, float alpha, float3 wo, float3 wi) {
  const float3 h = wo + wi;
  const float hl = length(h);
  if (!(hl > 0.0f) || wo.z <= 0.0f || wi.z <= 0.0f) return splat_float3(0.0f);
  const float3 m = h / hl;
  const float3 f = fresnel_schlick(f0, dot(wo, m));
  return f * (ggx_d(m, alpha) * ggx_g2(wo, wi, alpha) / (4.0f * wo.z * wi.z));
}

/* Density of reflecting by a visible normal: pdf_vnd(m) / (4 |wo.m|). */
inline float ggx_reflection_pdf(float alpha, float3 wo, float3 wi) {
  const float3 h = wo + wi;
  const float hl = length(h);
  if (!(hl > 0.0f) || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float3 m = h / hl;
  return ggx_pdf_visible_normal(wo, m, alpha) / (4.0f * fabs(dot(wo, m)));
}

inline float3 plastic_diffuse(Bsdf b, float3 wo, float3 wi) {
  if (!(bsdf_max3(b.specular) > 0.0f)) return b.diffuse * M_1_PI_F; /* no layer: Lambert */
  /* Ashikhmin-Shirley: 28/(23 pi) Rd (1 - Rs) (1 - (1 - cos_i/2)^5)(1 - (1 - cos_o/2)^5) */
  const float a = 1.0f - 0.5f * wi.z, c = 1.0f - 0.5f * wo.z;
  const float a5 = a * a * a * a * a, c5 = c * c * c * c * c;
  return b.diffuse * (1.0f - b.specular) * ((28.0f / (23.0f * M_PI_F)) * (1.0f - a5) * (1.0f - c5));
}

/* ---- dielectric ---- */

/* eta of the side wo is on over the other side, and the flipped frame. */
inline float dielectric_eta(Bsdf b, float3 wo) { return wo.z > 0.0f ? b.ior : 1.0f / b.ior; }

/* Generalised half vector of a refraction (Walter et al.), on the +z side. */
inline float3 refraction_half(float3 wo, float3 wi, float eta) {
  float3 m = wo + eta * wi; /* eta = n_i / n_o with n_o the side of wo */
  const float l = length(m);
  if (!(l > 0.0f)) return make_float3(0.0f, 0.0f, 1.0f);
  m /= l;
  return m.z < 0.0f ? -m : m;
}

inline float3 bsdf_base_eval(Bsdf b, float3 wo, float3 wi) {
  if (b.kind == BSDF_PLASTIC) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return splat_float3(0.0f);
    float3 f = plastic_diffuse(b, wo, wi);
    if (!bsdf_is_smooth(b) && bsdf_max3(b.specular) > 0.0f) f += ggx_reflection(b.specular, b.alpha, wo, wi);
    return f;
  }
  if (bsdf_is_smooth(b)) return splat_float3(0.0f); /* delta lobes only */
  if (b.kind == BSDF_CONDUCTOR) return ggx_reflection(b.specular, b.alpha, wo, wi);
#if HAS_DIELECTRIC
  /* rough dielectric */
  if (wo.z == 0.0f || wi.z == 0.0f) return splat_float3(0.0f);
  const float eta = dielectric_eta(b, wo); /* transmitted side over wo's side */
  const bool reflect = wo.z * wi.z > 0.0f;
  const float sign = wo.z > 0.0f ? 1.0f : -1.0f;
  const float3 wo_up = wo * sign, wi_up = wi * sign; /* wo on +z */
  float cos_t;
  if (reflect) {
    const float3 m = normalize(wo_up + wi_up);
    const float f = fresnel_dielectric(fabs(dot(wo_up, m)), 1.0f / eta, &cos_t);
    return splat_float3(f * ggx_d(m, b.alpha) * ggx_g2(wo_up, wi_up, b.alpha) / (4.0f * fabs(wo.z) * fabs(wi.z)));
  }
  const float3 m = refraction_half(wo_up, wi_up, eta);
  const float om = dot(wo_up, m), im = dot(wi_up, m);
  if (om <= 0.0f || im >= 0.0f) return splat_float3(0.0f); /* not a refraction through m */
  const float f = fresnel_dielectric(om, 1.0f / eta, &cos_t);
  const float denom = om + eta * im;
  const float value = (1.0f - f) * ggx_d(m, b.alpha) * ggx_g2(wo_up, wi_up, b.alpha) * fabs(im) * om /
                      (fabs(wo.z) * fabs(wi.z) * denom * denom);
  return b.diffuse * value; /* eta^2 * (1/eta^2): radiance scaling cancels Walter's eta_t^2; tinted */
#else
  return splat_float3(0.0f);
#endif
}

inline float bsdf_base_pdf(Bsdf b, float3 wo, float3 wi) {
  if (b.kind == BSDF_PLASTIC) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const float ps = plastic_specular_probability(b); /* smooth: a delta lobe, no density */
    const float diffuse_pdf = (1.0f - ps) * pdf_cosine_hemisphere(wi.z);
    if (ps == 0.0f || bsdf_is_smooth(b)) return diffuse_pdf; /* Lambert alone: no GGX term to evaluate */
    return ps * ggx_reflection_pdf(b.alpha, wo, wi) + diffuse_pdf;
  }
  if (bsdf_is_smooth(b)) return 0.0f;
  if (b.kind == BSDF_CONDUCTOR) return ggx_reflection_pdf(b.alpha, wo, wi);
#if HAS_DIELECTRIC
  if (wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
  const float eta = dielectric_eta(b, wo);
  const float sign = wo.z > 0.0f ? 1.0f : -1.0f;
  const float3 wo_up = wo * sign, wi_up = wi * sign;
  float cos_t;
  if (wo.z * wi.z > 0.0f) {
    const float3 m = normalize(wo_up + wi_up);
    const float f = fresnel_dielectric(fabs(dot(wo_up, m)), 1.0f / eta, &cos_t);
    return f * ggx_pdf_visible_normal(wo_up, m, b.alpha) / (4.0f * fabs(dot(wo_up, m)));
  }
  const float3 m = refraction_half(wo_up, wi_up, eta);
  const float om = dot(wo_up, m), im = dot(wi_up, m);
  if (om <= 0.0f || im >= 0.0f) return 0.0f;
  const float f = fresnel_dielectric(om, 1.0f / eta, &cos_t);
  const float denom = om + eta * im;
  /* dm/dwi = eta^2 |wi.m| / (wo.m + eta wi.m)^2 */
  return (1.0f - f) * ggx_pdf_visible_normal(wo_up, m, b.alpha) * eta * eta * fabs(im) / (denom * denom);
#else
  return 0.0f;
#endif
}

/* The base BSDF's sampling: see bsdf_sample below. */
inline bool bsdf_base_sample(Bsdf b, float3 wo, float3 u, float3* wi, float3* weight, float* pdf, uint* flags) {
  *flags = 0u;
  if (b.kind == BSDF_PLASTIC || b.kind == BSDF_CONDUCTOR) {
    if (wo.z <= 0.0f) return false;
    const bool smooth = bsdf_is_smooth(b);
    if (b.kind == BSDF_CONDUCTOR && smooth) {
      *wi = make_float3(-wo.x, -wo.y, wo.z);
      *pdf = 1.0f;
      *weight = fresnel_schlick(b.specular, wo.z);
      *flags = BSDF_SAMPLED_SPECULAR;
      return true;
    }
    const float ps = b.kind == BSDF_CONDUCTOR ? 1.0f : plastic_specular_probability(b);
    if (smooth && u.z < ps) { /* smooth plastic: the specular layer is a mirror */
      *wi = make_float3(-wo.x, -wo.y, wo.z);
      *pdf = ps;
      *weight = fresnel_schlick(b.specular, wo.z) / ps;
      *flags = BSDF_SAMPLED_SPECULAR;
      return true;
    }
    if (u.z < ps) {
      const float3 m = ggx_sample_visible_normal(wo, b.alpha, u.xy);
      *wi = reflect_dir(-wo, m);
    } else {
      *wi = sample_cosine_hemisphere(u.xy);
    }
    if (wi->z <= 0.0f) return false;
    *pdf = bsdf_base_pdf(b, wo, *wi);
    if (!(*pdf > 0.0f)) return false;
    *weight = bsdf_base_eval(b, wo, *wi) * (wi->z / *pdf);
    return true;
  }
#if HAS_DIELECTRIC
  /* dielectric */
  const float eta = dielectric_eta(b, wo);
  const float sign = wo.z > 0.0f ? 1.0f : -1.0f;
  const float3 wo_up = wo * sign;
  const float3 m = bsdf_is_smooth(b) ? make_float3(0.0f, 0.0f, 1.0f) : ggx_sample_visible_normal(wo_up, b.alpha, u.xy);
  const float om = dot(wo_up, m);
  if (!(om > 0.0f)) return false;
  float cos_t;
  const float f = fresnel_dielectric(om, 1.0f / eta, &cos_t);
  float3 w;
  if (u.z < f) {
    w = reflect_dir(-wo_up, m);
    if (w.z <= 0.0f) return false;
  } else {
    w = refract_dir(-wo_up, m, 1.0f / eta, om, cos_t);
    if (w.z >= 0.0f) return false;
    *flags |= BSDF_SAMPLED_TRANSMIT;
  }
  *wi = w * sign;
  if (bsdf_is_smooth(b)) {
    *flags |= BSDF_SAMPLED_SPECULAR;
    *pdf = u.z < f ? f : 1.0f - f;
    /* f (or 1 - f) / its probability; transmission scaled by 1/eta^2 and tinted */
    *weight = (*flags & BSDF_SAMPLED_TRANSMIT) ? b.diffuse * (1.0f / (eta * eta)) : splat_float3(1.0f);
    return true;
  }
  *pdf = bsdf_base_pdf(b, wo, *wi);
  if (!(*pdf > 0.0f)) return false;
  *weight = bsdf_base_eval(b, wo, *wi) * (fabs(wi->z) / *pdf);
  return true;
#else
  return false;
#endif
}

/* ---- the clear coat (HAS_CLEARCOAT) ----
 *
 * glTF's KHR_materials_clearcoat, as its specification writes the layering:
 * f = (1 - c Fc(wo)) f_base + c Fc(wo) D G / (4 |wo.z| |wi.z|), with Fc the
 * coat's Schlick reflectance for F0 = 0.04 (index 1.5) at the view's cosine
 * to the normal and D, G the coat's GGX terms (a mirror when smooth: a
 * delta lobe of weight c Fc). The base is what the material is without the
 * coat; dielectrics take no coat (the importer leaves it off). Sampling
 * picks the coat with probability clamp(c Fc(wo), 0.1, 0.9) (c > 0) and
 * the base otherwise; densities are the mixture's. The coat's lobe and its
 * Fresnel are taken about its own normal coat_n (its own normal map, or
 * the vertex normal under a normal-mapped base, as glTF asks). Energy: at most
 * (1 - c Fc) times the base's plus c Fc times a GGX lobe's, each <= 1, so
 * the sum is <= 1 (the white furnace in tests/host/test_bsdf.cpp). */
#define BSDF_COAT_F0 0.04f

/* Directions in the coat's own frame (its normal coat_n may differ from the
 * base's shading normal: glTF's clearcoatNormalTexture, or a smooth coat
 * over a normal-mapped base); a rotation, so densities carry over. */
typedef struct {
  float3 t, b, n;
} CoatFrame;
inline CoatFrame bsdf_coat_frame(Bsdf b) {
  CoatFrame f;
  f.n = b.coat_n;
  frame_from_normal(f.n, &f.t, &f.b);
  return f;
}
inline float3 coat_local(CoatFrame f, float3 w) { return make_float3(dot(w, f.t), dot(w, f.b), dot(w, f.n)); }
inline float3 coat_world(CoatFrame f, float3 w) { return w.x * f.t + w.y * f.b + w.z * f.n; }

inline float bsdf_coat_weight(Bsdf b, float3 wo) {
  const float m = clamp(1.0f - fabs(dot(wo, b.coat_n)), 0.0f, 1.0f);
  const float m2 = m * m;
  return b.coat * (BSDF_COAT_F0 + (1.0f - BSDF_COAT_F0) * (m2 * m2 * m));
}
inline float bsdf_coat_probability(Bsdf b, float3 wo) { return clamp(bsdf_coat_weight(b, wo), 0.1f, 0.9f); }
inline bool bsdf_coat_is_smooth(Bsdf b) { return b.coat_alpha < GGX_ALPHA_MIN; }
inline bool bsdf_has_coat(Bsdf b) {
#if HAS_CLEARCOAT
  return b.coat > 0.0f && b.kind != BSDF_DIELECTRIC;
#else
  (void)b;
  return false;
#endif
}

/* The coat's rough lobe D G / (4 |wo.z| |wi.z|) in its own frame, 0 for
 * directions under it. */
inline float bsdf_coat_lobe(Bsdf b, CoatFrame f, float3 wo, float3 wi) {
  return ggx_reflection(splat_float3(1.0f), b.coat_alpha, coat_local(f, wo), coat_local(f, wi)).x;
}

/* f(wo, wi) without the cosine (the rules at the top of this file). */
inline float3 bsdf_eval(Bsdf b, float3 wo, float3 wi) {
  if (!bsdf_has_coat(b)) return bsdf_base_eval(b, wo, wi);
  if (wo.z <= 0.0f || wi.z <= 0.0f) return splat_float3(0.0f);
  const float w = bsdf_coat_weight(b, wo);
  float3 f = (1.0f - w) * bsdf_base_eval(b, wo, wi);
  if (!bsdf_coat_is_smooth(b)) f += splat_float3(w * bsdf_coat_lobe(b, bsdf_coat_frame(b), wo, wi));
  return f;
}

inline float bsdf_pdf(Bsdf b, float3 wo, float3 wi) {
  if (!bsdf_has_coat(b)) return bsdf_base_pdf(b, wo, wi);
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float p = bsdf_coat_probability(b, wo);
  float coat = 0.0f;
  if (!bsdf_coat_is_smooth(b)) {
    const CoatFrame f = bsdf_coat_frame(b);
    coat = ggx_reflection_pdf(b.coat_alpha, coat_local(f, wo), coat_local(f, wi));
  }
  return p * coat + (1.0f - p) * bsdf_base_pdf(b, wo, wi);
}

/* Samples wi for wo with u in [0,1)^3 (u.z picks a lobe). Returns false when
 * no direction is produced (wo below a reflector, a sampled micro-normal that
 * sends wi below the surface). */
inline bool bsdf_sample(Bsdf b, float3 wo, float3 u, float3* wi, float3* weight, float* pdf, uint* flags) {
  if (!bsdf_has_coat(b)) return bsdf_base_sample(b, wo, u, wi, weight, pdf, flags);
  *flags = 0u;
  if (wo.z <= 0.0f) return false;
  const float p = bsdf_coat_probability(b, wo), w = bsdf_coat_weight(b, wo);
  if (u.z < p) {
    const CoatFrame f = bsdf_coat_frame(b);
    const float3 wo_c = coat_local(f, wo);
    if (wo_c.z <= 0.0f) return false;
    if (bsdf_coat_is_smooth(b)) {
      *wi = coat_world(f, make_float3(-wo_c.x, -wo_c.y, wo_c.z));
      if (wi->z <= 0.0f) return false; /* mirrored under the base's surface */
      *pdf = p;
      *weight = splat_float3(w / p);
      *flags = BSDF_SAMPLED_SPECULAR;
      return true;
    }
    *wi = coat_world(f, reflect_dir(-wo_c, ggx_sample_visible_normal(wo_c, b.coat_alpha, u.xy)));
  } else {
    /* The base's own choice, with u.z rescaled to [0, 1). */
    const float3 ub = make_float3(u.x, u.y, fmin((u.z - p) / (1.0f - p), 0x1.fffffep-1f));
    if (!bsdf_base_sample(b, wo, ub, wi, weight, pdf, flags)) return false;
    if (*flags & BSDF_SAMPLED_SPECULAR) { /* a delta lobe of the base, under the coat */
      *pdf *= 1.0f - p;
      *weight *= (1.0f - w) / (1.0f - p);
      return true;
    }
  }
  if (wi->z <= 0.0f) return false;
  *pdf = bsdf_pdf(b, wo, *wi);
  if (!(*pdf > 0.0f)) return false;
  *weight = bsdf_eval(b, wo, *wi) * (wi->z / *pdf);
  return true;
}

/* The aux passes (lib/film.h): does a path see through this surface to the
 * next one (a perfect mirror or smooth glass: the denoiser is told about
 * what is seen in it), and otherwise the surface's albedo as seen from wo:
 * plastic its diffuse albedo under the layer plus the layer's reflectance,
 * a rough conductor its Fresnel reflectance, rough glass white. */
inline bool bsdf_passes_aux_through(Bsdf b) { return bsdf_is_smooth(b) && b.kind != BSDF_PLASTIC && !bsdf_has_coat(b); }

/* Only delta lobes (a smooth conductor or glass, under no rough coat):
 * light sampling cannot reach any of them. */
inline bool bsdf_is_delta_only(Bsdf b) {
  return bsdf_is_smooth(b) && b.kind != BSDF_PLASTIC && !(bsdf_has_coat(b) && !bsdf_coat_is_smooth(b));
}
inline float3 bsdf_albedo(Bsdf b, float3 wo) {
  if (b.kind == BSDF_PLASTIC) return b.diffuse * (1.0f - b.specular) + b.specular;
  if (b.kind == BSDF_CONDUCTOR) return fresnel_schlick(b.specular, fabs(wo.z));
  return splat_float3(1.0f);
}

#endif /* CAUSTICA_LIB_BSDF_H */
