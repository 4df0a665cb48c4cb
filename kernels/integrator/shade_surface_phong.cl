#line 2 "kernels/integrator/shade_surface_phong.cl"
/* Stage: shade every hit of the ray queue, Whitted style (phong mode).
 *
 * Rules: a ray carries a weight (its share of the pixel); everything this
 * stage adds to the film or to a queue is scaled by it. Light that needs a
 * visibility test goes to the shadow queue with its full unoccluded value,
 * ray i's ray toward light l in slot i * light_count + l (queue.h);
 * direct terms without visibility (emission, ambient, background) go to the
 * film at once. Reflection and refraction rays go to the next queue while
 * depth < max_depth and their weight is not negligible. With
 * HAS_CAUSTICS, the local term also gathers the photon map's caustic
 * irradiance (lib/caustics.h). */

#include "lib/photon_grid.h"
#include "lib/caustics.h"
#include "lib/film.h"
#include "lib/lights.h"
#include "lib/material.h"
#include "lib/optics.h"
#include "lib/queue.h"
#include "lib/shading_point.h"
#include "lib/surface.h"
#include "lib/texture.h"

inline float max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

#if HAS_LIGHTS
/* n_dot_h ^ exponent (n_dot_h in [0, 1], exponent >= 0) as exp2(e log2 x):
 * within a few 1e-6 of pow where the lobe is above 1e-9, and 4x cheaper
 * than PoCL's pow, whose extended-precision logarithm and exponential were
 * a quarter of a phong render (Table 1's 400 spheres). 0^0 = 1. */
inline float blinn_lobe(float n_dot_h, float exponent) {
  if (!(n_dot_h > 0.0f)) return exponent == 0.0f ? 1.0f : 0.0f;
  return exp2(exponent * log2(n_dot_h));
}

/* Blinn-Phong for one delta light (a point, spot or directional light, or
 * the point that stands in for an area light: host/lights/), pushed as a
 * shadow ray. The registry's next-event estimation gives the direction
 * toward the light and how far the shadow ray goes (to the light's
 * position, or past the scene for a light at infinity); phong takes the
 * light's intensity in place of its radiance (no distance falloff). */
inline void shade_point_light(__global const Light* light, __global const float* environment, __global const Material* mat, float3 diffuse_colour,
                              SurfacePoint sp, float3 n_facing, float3 view, float3 weight, uint pixel,
                              uint slot, SHADOW_QUEUE_PARAMS(shadow)) {
  /* The shadow ray leaves on the geometric side the light is on; the
   * shading normal only weights the light. */
  const float3 geometric = dot(sp.normal, n_facing) >= 0.0f ? sp.normal : -sp.normal;
  const float3 origin = spawn_ray_origin(sp.position, sp.p_error, sp.normal, geometric);
  LightSample toward;
  if (!sample_light(light, environment, 1.0f, origin, (float2)(0.0f), &toward)) return;
  const float3 l = toward.wi;
  const float dist = toward.distance;
  const float n_dot_l = dot(n_facing, l);
  if (n_dot_l <= 0.0f) return;
  const float3 h = normalize(l + view);
  const float n_dot_h = fmax(dot(n_facing, h), 0.0f);
  if (dot(geometric, l) <= 0.0f) return; /* light behind the actual surface */
  const float3 diffuse = mat->diffuse.w * diffuse_colour * n_dot_l;
  const float3 specular = mat->specular.w * mat->specular.xyz * blinn_lobe(n_dot_h, mat->specular_exponent);
  const float3 contribution = weight * light_intensity_toward(light, environment, -l) * (diffuse + specular);
  if (max3(contribution) <= 0.0f) return;
  ShadowRecord ray;
  /* A point light is no surface (no error, no normal); the relative margin
   * still keeps a surface through the light from shadowing it. */
  ray.origin = (float4)(origin, 0.0f);
  ray.dir = (float4)(l, 0.0f);
  ray.contribution = (float4)(contribution, 0.0f);
  ray.pixel = pixel;
  ray.tmax = shadow_ray_tmax(dist, l, (float3)(0.0f), (float3)(0.0f));
  shadow_store(SHADOW_QUEUE_ARGS(shadow), slot, ray);
}
#endif

/* Pushes a specular child of `parent` unless its weight is negligible. */
inline void push_specular(PATH_QUEUE_PARAMS(next), uint capacity, float min_weight, PathRecord parent,
                          float3 origin, float3 dir, float3 weight) {
  if (!(max3(weight) > min_weight)) return;
  PathRecord child;
  child.origin = (float4)(origin, 0.0f);
  child.dir = (float4)(dir, 0.0f);
  child.throughput = (float4)(weight, 0.0f);
  child.pixel = parent.pixel;
  child.depth = parent.depth + 1u;
  child.sample = parent.sample;
  child.bsdf_pdf = 0.0f;
  child.flags = PATH_SPECULAR;
  child.cone_width = 0.0f; /* Whitted rays keep no cone */
  child.cone_spread = 0.0f;
  child.light_normal = LIGHT_NORMAL_NONE;
  path_push(PATH_QUEUE_ARGS(next), capacity, child);
}

__kernel void shade_surface_phong(SCENE_SURFACE_PARAMS, __global const Light* restrict lights,
                                  ShadeParams params, PATH_QUEUE_PARAMS(in), __global const Hit* restrict hits,
                                  FILM_PARAMS, PATH_QUEUE_PARAMS(next), volatile __global uint* restrict cleared_count,
                                  SHADOW_QUEUE_PARAMS(shadow), volatile __global uint* restrict rays_traced
#if HAS_CAUSTICS
                                  , PHOTON_GRID_PARAMS, float caustic_radius
#endif
) {
  const uint i = get_global_id(0);
  const uint count = *in_count;
  if (i == 0) { /* the wave loop's counters (host/render/wave_loop.h) */
    *cleared_count = 0u;                        /* the queue the next iteration's shade stage pushes into */
    *shadow_count = count * params.light_count; /* ray i's shadow slots: [i L, (i + 1) L) */
    atomic_add(rays_traced, count);
  }
  if (i >= count) return;
#if HAS_LIGHTS
  /* This ray's shadow slots: empty unless a light below fills its own. */
  for (uint l = 0; l < params.light_count; ++l) shadow_mark_empty(SHADOW_QUEUE_ARGS(shadow), i * params.light_count + l);
#endif
  const Hit hit = hits[i];
  const PathRecord ray = path_load(PATH_QUEUE_ARGS(in), i);
  const float3 weight = ray.throughput.xyz;
  const uint pixel = ray.pixel;

  if (hit.prim == PRIM_NONE) {
#if HAS_ENVIRONMENT
    film_add(FILM_ARGS, pixel, weight * environment_radiance(environment, ray.dir.xyz));
#else
    film_add(FILM_ARGS, pixel, weight * params.background.xyz);
#endif
    return;
  }

  const float3 d = ray.dir.xyz;
  const SurfacePoint sp = shading_point_at(SCENE_SURFACE_ARGS, hit, ray.origin.xyz, d);
  __global const Material* mat = &materials[sp.material];
  const bool front = dot(sp.normal, d) < 0.0f;
  const float3 n = front ? sp.normal : -sp.normal;                  /* geometric, faces the ray */
  const float3 ns = front ? sp.shading_normal : -sp.shading_normal; /* shading, same side */
  const float3 diffuse_colour = material_diffuse_colour(mat, textures, texels, sp.uv, sp.colour);
  film_add(FILM_ARGS, pixel, weight * mat->emission.xyz * material_emission_texel(mat, textures, texels, sp.uv));

  /* Split the ray's weight between the local Phong term and the specular
   * children: mirror by reflectivity; dielectric by Fresnel. */
  float local_share = 1.0f;
  float3 reflect_weight = (float3)(0.0f);
  float3 refract_weight = (float3)(0.0f);
  /* Specular directions follow the shading normal unless its mirror
   * direction would dive below the actual surface (interpolated normals at
   * grazing angles); then the geometric normal is used. */
  const float3 n_spec = dot(reflect_dir(d, ns), n) > 0.0f ? ns : n;
  float cos_i = -dot(d, n_spec), cos_t = 0.0f;
  float eta = 1.0f;
  bool refractive = false;
#if HAS_REFRACTION
  if (mat->flags & MATERIAL_REFRACTIVE) {
    refractive = true;
    eta = front ? 1.0f / mat->ior : mat->ior;
    const float fresnel = fresnel_dielectric(cos_i, eta, &cos_t);
    local_share = 0.0f;
    reflect_weight = weight * fresnel;
    refract_weight = weight * (1.0f - fresnel);
  }
#endif
#if HAS_REFLECTION
  if (!refractive && (mat->flags & MATERIAL_REFLECTIVE)) {
    const float r = clamp(mat->reflectivity, 0.0f, 1.0f);
    local_share = 1.0f - r;
    reflect_weight = weight * r;
  }
#endif

  if (local_share > 0.0f) {
    const float3 local_weight = weight * local_share;
    film_add(FILM_ARGS, pixel, local_weight * mat->ka * params.ambient_light.xyz * diffuse_colour);
#if HAS_CAUSTICS
    film_add(FILM_ARGS, pixel, local_weight * mat->diffuse.w * diffuse_colour *
                                   phong_caustic_irradiance(PHOTON_GRID_ARGS, sp.position, n, caustic_radius));
#endif
#if HAS_LIGHTS
    for (uint l = 0; l < params.light_count; ++l)
      shade_point_light(&lights[l], environment, mat, diffuse_colour, sp, ns, -d, local_weight, pixel, i * params.light_count + l,
                        SHADOW_QUEUE_ARGS(shadow));
#endif
  }

  if (ray.depth >= params.max_depth) return;
  push_specular(PATH_QUEUE_ARGS(next), params.ray_capacity, params.min_weight, ray,
                spawn_ray_origin(sp.position, sp.p_error, sp.normal, n),
                reflect_dir(d, n_spec), reflect_weight);
  push_specular(PATH_QUEUE_ARGS(next), params.ray_capacity, params.min_weight, ray,
                spawn_ray_origin(sp.position, sp.p_error, sp.normal, -n),
                refract_dir(d, n_spec, eta, cos_i, cos_t), refract_weight);
}
