#line 2 "tests/kernels/stiff/shadow_rays.cl"
/* tests/stiff/test_shadow_rays.cpp's device side: next-event estimation's
 * shadow rays made as shade_surface_path makes them (sample_light, then
 * spawn_ray_to), traced against the light's own primitives. A kernel
 * because the test is of what the device computes: the sampled point, the
 * error bounds and the occlusion test as the renderer builds them. */
#include "lib/bvh_traverse.h"
#include "lib/lights.h"
#include "tests/kernels/stiff/random.h"

/* counts: 0 samples taken, 1 occluded by the light itself, 2 sample off the
 * light's surface, 3 non-finite direction or tmax.
 * points: shading point (xyz) per work-item; its surface normal faces the
 * light's centre and its error bound is that of a point made by a few
 * roundings of its coordinates. */
__kernel void shadow_rays(__global const float4* points, uint n, __global const Light* light,
                          __global const Sphere* spheres, __global const Cylinder* cylinders,
                          __global const Triangle* triangles, __global const uint* prims, uint prim_count,
                          float surface_tolerance, volatile __global uint* counts, __global float2* weights) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  weights[i] = (float2)(0.0f);
  const float3 p = points[i].xyz;
  const float3 n_p = normalize(light->p0.xyz - p);
  const float3 p_error = error_gamma(4.0f) * fabs(p);
  uint s = mix32(i * 0x2545f491u + 17u);
  const float2 u = (float2)(stiff_unit_float(&s), stiff_unit_float(&s));
  LightSample ls;
  if (!sample_light(light, (__global const float*)0, 1.0f, p, u, &ls) /* no environment */) return;
  atomic_inc(&counts[0]);
  float3 dir;
  float tmax;
  const float3 origin = spawn_ray_to(p, p_error, n_p, ls.point, ls.p_error, ls.normal, &dir, &tmax);
  if (!(isfinite(tmax) && isfinite(dir.x) && isfinite(dir.y) && isfinite(dir.z))) atomic_inc(&counts[3]);
  /* The sample's weight in next-event estimation (radiance / density), and
   * that weight again when the light shadows it. */
  weights[i].x = 1.0f / ls.pdf;
  for (uint k = 0; k < prim_count; ++k) {
    Hit h = hit_none(tmax);
    if (intersect_prim_ref(spheres, cylinders, triangles, prims[k], origin, dir, 0.0f, &h)) {
      atomic_inc(&counts[1]);
      weights[i].y = 1.0f / ls.pdf;
      break;
    }
  }
  /* On the surface: the distance to it from the sampled point, by kind. */
  const float3 q = ls.point;
  float off = 0.0f;
  if (light->kind == LIGHT_SPHERE) {
    off = fabs(length(q - light->p0.xyz) - light->p0.w);
  } else if (light->kind == LIGHT_CYLINDER) {
    const float3 rel = q - light->p0.xyz, axis = light->p1.xyz;
    const float z = dot(rel, axis), r = light->p0.w, h = light->p1.w;
    const float radial = length(rel - z * axis);
    off = fabs(fabs(z) - h) < fabs(radial - r) ? fmax(fabs(fabs(z) - h), fmax(radial - r, 0.0f))
                                               : fmax(fabs(radial - r), fmax(fabs(z) - h, 0.0f));
  } else {
    const float3 n_l = light->kind == LIGHT_RECT ? rect_light_normal(light) : triangle_light_normal(light);
    off = fabs(dot(q - light->p0.xyz, n_l));
  }
  if (!(off <= surface_tolerance)) atomic_inc(&counts[2]);
}
