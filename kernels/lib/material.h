#line 2 "kernels/lib/material.h"
/* The coursework material (Material, shared/types.h) as the path tracer's
 * scattering model (lib/bsdf.h). The mapping, documented for users in
 * scenes/FORMAT.md ("Path mode"):
 *   isrefractive: dielectric of index `ior`, smooth unless `roughness`;
 *   isreflective: conductor of reflectance reflectivity x specularcolor,
 *     a mirror unless `roughness`;
 *   otherwise plastic: diffuse albedo kd x diffusecolor (x texture), a GGX
 *     layer of normal reflectance ks x specularcolor with
 *     alpha = sqrt(2 / (specularexponent + 2)) unless `roughness` is given;
 *     `metallic` m moves it toward a conductor: specular = mix(specular,
 *     diffuse, m), diffuse x (1 - m), a pure conductor at m = 1;
 *   a roughness_texture (glTF's metallicRoughnessTexture) scales alpha by
 *     G^2 and metallic by B per texel (texel_scale).
 * Colours are clamped to [0, 1]; emission is added where a path hits the
 * surface, not here (material_emission_texel: what an emission texture
 * makes of it at a point). */
#ifndef CAUSTICA_LIB_MATERIAL_H
#define CAUSTICA_LIB_MATERIAL_H

#include "lib/bsdf.h"
#include "lib/rng.h"
#include "lib/surface.h"
#include "shared/photon.h"
#include "shared/types.h"
#include "lib/texture.h"

/* texel_scale: what the material's data textures (shared/types.h) make of
 * its numbers at this point: x multiplies GGX alpha, y metallic, z the
 * coat's weight, w the coat's alpha; all 1 without them
 * (material_texel_scale below). u_layer in [0, 1)
 * picks the layer of a partly transmissive material (volume.w > 0: glTF's
 * transmissionFactor < 1): glass where u_layer >= volume.w, else the
 * opaque base (plastic or conductor). One layer per shading point, used
 * for its light sampling and its bounce alike, is an unbiased one-sample
 * estimate of the mixture the specification writes. */
inline Bsdf bsdf_of_material(__global const Material* m, float3 diffuse_colour, float4 texel_scale, float u_layer) {
  Bsdf b;
  b.ior = m->ior;
  b.diffuse = splat_float3(0.0f);
  b.specular = splat_float3(0.0f);
  b.coat = 0.0f;
  b.coat_alpha = 0.0f;
  b.coat_n = make_float3(0.0f, 0.0f, 1.0f); /* the shading frame's z until material_coat_normal sets it */
  const bool given = m->roughness >= 0.0f;
  if ((m->flags & MATERIAL_REFRACTIVE) && u_layer >= m->volume.w) {
    b.kind = BSDF_DIELECTRIC;
    b.alpha = (given ? m->roughness : 0.0f) * texel_scale.x;
    b.diffuse = (m->flags & MATERIAL_TINTED_TRANSMISSION) ? clamp(diffuse_colour, 0.0f, 1.0f) : splat_float3(1.0f);
    return b; /* glass takes no coat */
  }
  b.coat = m->clearcoat * texel_scale.z;
  b.coat_alpha = m->clearcoat_alpha * texel_scale.w;
  if ((m->flags & MATERIAL_REFLECTIVE) && !(m->flags & MATERIAL_REFRACTIVE)) {
    b.kind = BSDF_CONDUCTOR;
    b.specular = clamp(m->reflectivity * m->specular.xyz, 0.0f, 1.0f);
    b.alpha = (given ? m->roughness : 0.0f) * texel_scale.x;
  } else {
    b.alpha = (given ? m->roughness : sqrt(2.0f / (fmax(m->specular_exponent, 0.0f) + 2.0f))) * texel_scale.x;
    const float3 diffuse = clamp(m->diffuse.w * diffuse_colour, 0.0f, 1.0f);
    const float3 specular = clamp(m->specular.w * m->specular.xyz, 0.0f, 1.0f);
    const float metallic = clamp(m->metallic * texel_scale.y, 0.0f, 1.0f);
    if (metallic >= 1.0f) {
      b.kind = BSDF_CONDUCTOR;
      b.specular = diffuse;
    } else {
      b.kind = BSDF_PLASTIC;
      b.specular = mix(specular, diffuse, metallic);
      b.diffuse = diffuse * (1.0f - metallic);
    }
  }
  return b;
}

#if HAS_TEXTURES
/* The texel scales of m's data textures at uv (bsdf_of_material's
 * texel_scale): glTF's roughness is G x factor and alpha its square, so
 * alpha scales by G^2 and metallic by B (roughness_texture); the coat's
 * weight by R of clearcoat_texture, its alpha by G^2 of
 * clearcoat_roughness_texture. Texels are linear data
 * (host/scene/gltf_textures.cpp stores them so). */
inline float4 material_texel_scale(__global const Material* m, __global const Texture* textures,
                                   __global const half* texels, float2 uv) {
  float2 base = make_float2(1.0f, 1.0f);
  float coat = 1.0f, coat_alpha = 1.0f;
  if (m->roughness_texture >= 0) {
    const float3 t = clamp(texture_lookup(textures, texels, m->roughness_texture, uv), 0.0f, 1.0f);
    base = make_float2(t.y * t.y, t.z);
  }
  if (m->clearcoat_texture >= 0)
    coat = clamp(texture_lookup(textures, texels, m->clearcoat_texture, uv).x, 0.0f, 1.0f);
  if (m->clearcoat_roughness_texture >= 0) {
    const float g = clamp(texture_lookup(textures, texels, m->clearcoat_roughness_texture, uv).y, 0.0f, 1.0f);
    coat_alpha = g * g;
  }
  return make_float4(base.x, base.y, coat, coat_alpha);
}
#endif

/* Texture `index`'s texel at uv, or `otherwise` where there is none (-1,
 * or a program without HAS_TEXTURES, where no material has one). */
inline float3 material_texel_or(__global const Texture* textures, __global const ushort* texels, int index, float2 uv,
                                float3 otherwise) {
#if HAS_TEXTURES
  if (index >= 0) return texture_lookup(textures, (__global const half*)texels, index, uv);
#endif
  (void)textures;
  (void)texels;
  (void)index;
  (void)uv;
  return otherwise;
}

/* m's diffuse colour at uv: its texture's texel (an image or checker
 * texture replaces the colour; with MATERIAL_TEXTURE_SCALES, as glTF's
 * base colour, it scales it), else its own; times the surface's vertex
 * colour (glTF's COLOR_0; 1 where there is none: exactly the colour). */
inline float3 material_diffuse_colour(__global const Material* m, __global const Texture* textures,
                                      __global const ushort* texels, float2 uv, float3 vertex_colour) {
  if (m->flags & MATERIAL_TEXTURE_SCALES)
    return vertex_colour * (m->diffuse.xyz * material_texel_or(textures, texels, m->texture, uv, splat_float3(1.0f)));
  return vertex_colour * material_texel_or(textures, texels, m->texture, uv, m->diffuse.xyz);
}

/* m's BSDF at a surface point's uv, its colour and roughness texels
 * applied: the one material -> BSDF set-up of the path tracer's vertices
 * and the photon pass's bounces (the photon map must scatter as the paths
 * it stands in for do). */
inline Bsdf material_bsdf_at(__global const Material* m, __global const Texture* textures,
                             __global const ushort* texels, float2 uv, float3 vertex_colour, float u_layer) {
#if HAS_TEXTURES
  const float4 texel_scale = material_texel_scale(m, textures, (__global const half*)texels, uv);
#else
  const float4 texel_scale = make_float4(1.0f, 1.0f, 1.0f, 1.0f);
#endif
  return bsdf_of_material(m, material_diffuse_colour(m, textures, texels, uv, vertex_colour), texel_scale, u_layer);
}

/* What scales m's emission at uv: its emission_texture's texel (glTF's
 * emissiveTexture, stored linear like base colour), 1 without one (or
 * without HAS_TEXTURES, where no material has one). */
inline float3 material_emission_texel(__global const Material* m, __global const Texture* textures,
                                      __global const ushort* texels, float2 uv) {
  return material_texel_or(textures, texels, m->emission_texture, uv, splat_float3(1.0f));
}

/* bsdf_of_material's u_layer for m at a vertex: a uniform random number
 * (key, counter) where m has two layers to pick from (a refractive
 * material with an opaque share, volume.w > 0), else 0, which picks glass
 * for every refractive material and is unread by the rest: the hash is
 * paid only where there is a choice. */
inline float material_layer_u(__global const Material* m, uint key, uint counter) {
  if (!(m->flags & MATERIAL_REFRACTIVE) || !(m->volume.w > 0.0f)) return 0.0f;
  return random_float(key, counter);
}

/* The coat's normal in shading frame f (Bsdf.coat_n): sp's coat normal,
 * turned over as the frame turned the shading normal toward the path;
 * exactly (0, 0, 1) where it is the shading normal (no normal map on
 * either), and where it would fall below the frame's surface. */
inline float3 material_coat_normal(const SurfacePoint* sp, const ShadingFrame* f) {
  const float3 z = make_float3(0.0f, 0.0f, 1.0f);
  if (sp->coat_normal.x == sp->shading_normal.x && sp->coat_normal.y == sp->shading_normal.y &&
      sp->coat_normal.z == sp->shading_normal.z)
    return z;
  const float3 c = dot(f->ng, sp->normal) < 0.0f ? -sp->coat_normal : sp->coat_normal;
  const float3 l = frame_to_local(c, f->t, f->b, f->n);
  const float l2 = dot(l, l);
  return l.z > 0.0f && l2 > 1e-12f ? l * rsqrt(l2) : z;
}

/* What survives of light that crossed `distance` inside m to reach sp
 * along d (KHR_materials_volume: Beer-Lambert, exp(-sigma distance)):
 * applied where a path or photon leaves the material, that is where d runs
 * along its outward normal; 1 elsewhere, and for materials that absorb
 * nothing. Nested or overlapping volumes are not tracked. */
inline float3 material_transmittance_to(__global const Material* m, const SurfacePoint* sp, float3 d, float distance) {
#if HAS_DIELECTRIC
  if ((m->flags & MATERIAL_ATTENUATES) && dot(d, sp->normal) > 0.0f) /* per channel: the host has no exp(float3) */
    return make_float3(exp(-m->volume.x * distance), exp(-m->volume.y * distance), exp(-m->volume.z * distance));
#else
  (void)m;
  (void)sp;
  (void)d;
  (void)distance;
#endif
  return splat_float3(1.0f);
}

/* A caster of caustics: a smooth enough conductor or dielectric (the photon
 * pass's caster/receiver split, shared/photon.h); plastic receives. The
 * host's scene analysis asks the same question of the same code. */
inline bool bsdf_casts_caustics(Bsdf b) { return b.kind != BSDF_PLASTIC && b.alpha < CAUSTIC_CASTER_ALPHA; }

#endif /* CAUSTICA_LIB_MATERIAL_H */
