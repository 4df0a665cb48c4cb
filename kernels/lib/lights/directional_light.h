#line 2 "kernels/lib/lights/directional_light.h"
/* Directional light ("directional"; glTF KHR_lights_punctual's directional,
 * a sun): a delta light at infinity, all of whose light travels along one
 * direction. p1.xyz = d, the unit direction the light travels (it arrives
 * from -d); emitted.xyz = E, its irradiance on a surface facing it (W/m^2;
 * glTF's colour x intensity in lux, read as such); p0.xyz = centre and
 * p0.w = radius of a sphere bounding the scene, which the host fills in
 * when it uploads the light (host/lights/directional_light.cpp): shadow
 * rays aim past it, photons start on a disk of it. A surface point with
 * normal n receives E max(0, dot(n, -d)) wherever nothing blocks -d:
 * next-event estimation returns wi = -d and "radiance" E with density 1
 * (the delta's), so the estimate is f E cos. Phong shades it as its point
 * lights, with intensity E and no falloff (kd E cos + ks E lobe). Photons
 * cross a disk of the bounding sphere facing -d, starting outside the
 * scene, each carrying E pi R^2 (the irradiance through the disk's area;
 * guided emission crosses the casters' sphere's disk instead, as the
 * environment's do: emit_photons.cl). Functions as in
 * lights/light_common.h. */
#ifndef CAUSTICA_LIB_LIGHTS_DIRECTIONAL_LIGHT_H
#define CAUSTICA_LIB_LIGHTS_DIRECTIONAL_LIGHT_H

#include "lib/lights/light_common.h"

inline bool directional_light_sample(__global const Light* l, float3 p, float2 u, LightSample* s) {
  (void)u;
  sample_from_infinity(l->p0, p, -l->p1.xyz, s);
  s->radiance = l->emitted.xyz;
  s->pdf = 1.0f;
  s->delta = true;
  return true;
}

inline float directional_light_pdf(__global const Light* l, float3 p, float3 q, float3 wi) {
  (void)l; (void)p; (void)q; (void)wi;
  return 0.0f;
}

/* Phong's intensity: E (it only ever shades along d). */
inline float3 directional_light_intensity_toward(__global const Light* l, float3 w) {
  (void)w;
  return l->emitted.xyz;
}

/* A point of the unit disk (z = 0), placed across the bounding sphere's
 * disk by the emission below. */
inline float3 directional_light_emission_point(__global const Light* l, float2 u, float3* p_error, float3* n) {
  (void)l;
  *p_error = splat_float3(0.0f);
  *n = splat_float3(0.0f);
  const float2 d = sample_concentric_disk(u);
  return make_float3(d.x, d.y, 0.0f);
}

/* A photon through the disk of sphere `target` (the scene's bounding
 * sphere, or guided, one around the casters) facing -d: flux E pi r^2. */
inline float3 directional_emit_through(__global const Light* l, float4 target, float3 point, float3* origin,
                                       float3* dir) {
  return l->emitted.xyz * start_from_infinity(l->p0, target, -l->p1.xyz, point, origin, dir);
}

inline float3 directional_light_emit(__global const Light* l, float3 point, float3 p_error, float3 n, float2 u,
                                     float u_side, float3* origin, float3* dir) {
  (void)p_error; (void)n; (void)u; (void)u_side;
  return directional_emit_through(l, l->p0, point, origin, dir);
}

/* Guided emission aims from a point at the casters; this light has no
 * point, so emit_photons guides its photons through
 * directional_emit_through instead (this is never called). */
inline float3 directional_light_emitted_toward(__global const Light* l, float3 point, float3 p_error, float3 n,
                                               float3* dir, float pdf, float3* origin) {
  (void)l; (void)p_error; (void)n; (void)pdf;
  *origin = point;
  *dir = splat_float3(0.0f);
  return splat_float3(0.0f);
}

#endif /* CAUSTICA_LIB_LIGHTS_DIRECTIONAL_LIGHT_H */
