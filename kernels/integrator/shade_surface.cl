#line 2 "kernels/integrator/shade_surface.cl"
/* Stage 3: shade every hit of the ray queue (binary or Whitted/Phong).
 *
 * Rules: a ray carries a weight (its share of the pixel); everything this
 * stage adds to the film or to a queue is scaled by it. Light that needs a
 * visibility test goes to the shadow queue with its full unoccluded value;
 * direct terms without visibility (ambient, background, binary red) go to the
 * film at once. Reflection and refraction rays go to the next queue while
 * depth < max_depth and their weight is not negligible. */

#include "lib/film.h"
#include "lib/optics.h"
#include "lib/queue.h"
#include "lib/surface.h"
#include "lib/texture.h"

inline void push_ray(volatile __global uint* count, uint capacity, RAY_QUEUE_PARAMS(q), float3 origin,
                     float3 dir, float3 weight, uint depth, uint pixel) {
  const uint slot = queue_reserve(count, capacity);
  if (slot == 0xFFFFFFFFu) return;
  q_origin[slot] = (float4)(origin, 0.0f);
  q_dir[slot] = (float4)(dir, 0.0f);
  q_weight[slot] = (float4)(weight, as_float(depth));
  q_pixel[slot] = pixel;
}

inline float max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

#ifdef HAS_LIGHTS
/* Blinn-Phong for one point light, pushed as a shadow ray. */
inline void shade_point_light(__global const PointLight* light, __global const Material* mat, float3 diffuse_colour,
                              SurfacePoint sp, float3 n_facing, float3 view, float3 weight, uint pixel,
                              volatile __global uint* shadow_count, uint shadow_capacity,
                              SHADOW_QUEUE_PARAMS(shadow)) {
  /* The shadow ray leaves on the geometric side the light is on; the
   * shading normal only weights the light. */
  const float3 geometric = dot(sp.normal, n_facing) >= 0.0f ? sp.normal : -sp.normal;
  const float3 origin = spawn_point(sp, geometric);
  const float3 to_light = light->position.xyz - origin;
  const float dist = length(to_light);
  if (!(dist > 0.0f)) return;
  const float3 l = to_light / dist;
  const float n_dot_l = dot(n_facing, l);
  if (n_dot_l <= 0.0f) return;
  const float3 h = normalize(l + view);
  const float n_dot_h = fmax(dot(n_facing, h), 0.0f);
  if (dot(geometric, l) <= 0.0f) return; /* light behind the actual surface */
  const float3 diffuse = mat->diffuse.w * diffuse_colour * n_dot_l;
  const float3 specular = mat->specular.w * mat->specular.xyz * pow(n_dot_h, mat->specular_exponent);
  const float3 contribution = weight * light->intensity.xyz * (diffuse + specular);
  if (max3(contribution) <= 0.0f) return;
  const uint slot = queue_reserve(shadow_count, shadow_capacity);
  if (slot == 0xFFFFFFFFu) return;
  shadow_origin[slot] = (float4)(origin, dist * (1.0f - 1e-5f));
  shadow_dir[slot] = (float4)(l, 0.0f);
  shadow_contribution[slot] = (float4)(contribution, 0.0f);
  shadow_pixel[slot] = pixel;
}
#endif

__kernel void shade_surface(__global const Sphere* restrict spheres, __global const Cylinder* restrict cylinders,
                            __global const Triangle* restrict triangles,
                            __global const TriangleShading* restrict triangle_shading,
                            __global const Material* restrict materials, __global const Texture* restrict textures,
                            __global const ushort* restrict texels,
                            __global const PointLight* restrict lights, ShadeParams params,
                            __global const uint* restrict ray_count, RAY_QUEUE_PARAMS(in),
                            __global const float4* restrict hits, __global ulong* restrict film,
                            volatile __global uint* next_count, RAY_QUEUE_PARAMS(next),
                            volatile __global uint* shadow_count, SHADOW_QUEUE_PARAMS(shadow)) {
  const uint i = get_global_id(0);
  if (i >= *ray_count) return;
  const float4 hit_bits = hits[i];
  const float4 weight_depth = in_weight[i];
  const float3 weight = weight_depth.xyz;
  const uint depth = as_uint(weight_depth.w);
  const uint pixel = in_pixel[i];
  Hit hit;
  hit.t = hit_bits.x;
  hit.u = hit_bits.y;
  hit.v = hit_bits.z;
  hit.prim = as_uint(hit_bits.w);

  if (params.mode == RENDER_MODE_BINARY) {
    if (hit.prim != PRIM_NONE) film_add(film, pixel, weight * (float3)(1.0f, 0.0f, 0.0f));
    return;
  }
  if (hit.prim == PRIM_NONE) {
    film_add(film, pixel, weight * params.background.xyz);
    return;
  }

  const float3 d = in_dir[i].xyz;
  const SurfacePoint sp = surface_at(spheres, cylinders, triangles, triangle_shading, hit, in_origin[i].xyz, d);
  __global const Material* mat = &materials[sp.material];
  const bool front = dot(sp.normal, d) < 0.0f;
  const float3 n = front ? sp.normal : -sp.normal;                  /* geometric, faces the ray */
  const float3 ns = front ? sp.shading_normal : -sp.shading_normal; /* shading, same side */
  float3 diffuse_colour = mat->diffuse.xyz;
#ifdef HAS_TEXTURES
  /* An image or checker texture replaces the diffuse colour. */
  if (mat->texture >= 0) diffuse_colour = texture_lookup(textures, (__global const half*)texels, mat->texture, sp.uv);
#endif
  film_add(film, pixel, weight * mat->emission.xyz);

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
#ifdef HAS_REFRACTION
  if (mat->flags & MATERIAL_REFRACTIVE) {
    refractive = true;
    eta = front ? 1.0f / mat->ior : mat->ior;
    const float fresnel = fresnel_dielectric(cos_i, eta, &cos_t);
    local_share = 0.0f;
    reflect_weight = weight * fresnel;
    refract_weight = weight * (1.0f - fresnel);
  }
#endif
#ifdef HAS_REFLECTION
  if (!refractive && (mat->flags & MATERIAL_REFLECTIVE)) {
    const float r = clamp(mat->reflectivity, 0.0f, 1.0f);
    local_share = 1.0f - r;
    reflect_weight = weight * r;
  }
#endif

  if (local_share > 0.0f) {
    const float3 local_weight = weight * local_share;
    film_add(film, pixel, local_weight * mat->ka * params.ambient_light.xyz * diffuse_colour);
#ifdef HAS_LIGHTS
    for (uint l = 0; l < params.light_count; ++l)
      shade_point_light(&lights[l], mat, diffuse_colour, sp, ns, -d, local_weight, pixel, shadow_count,
                        params.shadow_capacity, shadow_origin, shadow_dir, shadow_contribution, shadow_pixel);
#endif
  }

  if (depth >= params.max_depth) return;
  if (max3(reflect_weight) > params.min_weight)
    push_ray(next_count, params.ray_capacity, RAY_QUEUE_ARGS(next), spawn_point(sp, n),
             reflect_dir(d, n_spec), reflect_weight, depth + 1, pixel);
  if (max3(refract_weight) > params.min_weight)
    push_ray(next_count, params.ray_capacity, RAY_QUEUE_ARGS(next), spawn_point(sp, -n),
             refract_dir(d, n_spec, eta, cos_i, cos_t), refract_weight, depth + 1, pixel);
}
