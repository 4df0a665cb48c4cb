#line 2 "tests/kernels/stiff/self_intersection.cl"
/* tests/stiff/test_self_intersection.cpp's device side: per hit point,
 * rays spawned from it (spawn_ray_origin, shadow_ray_tmax) and re-traced
 * against the same primitive, counting the spurious hits. A kernel because
 * the test is of the device build: it runs under the renderer's
 * -cl-fast-relaxed-math and without. */
#include "lib/bvh_traverse.h"
#include "lib/surface.h"
#include "tests/kernels/stiff/random.h"

float3 unit_vector(uint* s) {
  const float z = 1.0f - 2.0f * stiff_unit_float(s), phi = 6.2831853f * stiff_unit_float(s);
  const float r = sqrt(fmax(0.0f, 1.0f - z * z));
  return (float3)(r * cos(phi), r * sin(phi), z);
}
/* A direction on nf's side with cos >= min_cos. */
float3 hemisphere(uint* s, float3 nf, float min_cos) {
  float3 v = unit_vector(s);
  if (dot(v, nf) < 0.0f) v = -v;
  if (dot(v, nf) < min_cos) v = normalize(v + (min_cos - dot(v, nf)) * nf * 1.01f);
  return v;
}

/* counts: 0 hit points, 1 rays, 2 spurious, 3 non-finite origins */
__kernel void reintersect(__global const float4* rays, uint n, uint per_hit, __global const Sphere* spheres,
                          __global const Cylinder* cylinders, __global const Triangle* triangles, uint ref, float size,
                          volatile __global uint* counts, __global float4* example) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float3 o = rays[2 * i].xyz, d = rays[2 * i + 1].xyz;
  Hit h = hit_none(RAY_T_FAR);
  if (!intersect_prim_ref(spheres, cylinders, triangles, ref, o, d, 0.0f, &h)) return;
  atomic_inc(&counts[0]);
  const SurfacePoint sp = surface_at(spheres, cylinders, triangles, (__global const TriangleShading*)0, h, o, d);
  const float3 nf = dot(sp.normal, d) < 0.0f ? sp.normal : -sp.normal;
  const bool closed = prim_ref_type(ref) != PRIM_TRIANGLE;
  uint s = mix32(i * 0x2545f491u + 1u);
  uint spurious = 0, nonfinite = 0;
  for (uint j = 0; j < per_hit; ++j) {
    const uint kind = j & 3u;
    float3 dir;
    float tmax = RAY_T_FAR;
    bool inward = false;
    if (kind == 0u) { /* reflection about a jittered normal, kept outside */
      const float3 m = normalize(nf + 0.3f * unit_vector(&s));
      dir = d - 2.0f * dot(d, m) * m;
      if (dot(dir, nf) <= 0.0f) dir = d - 2.0f * dot(d, nf) * nf;
    } else if (kind == 1u) { /* refraction into the shape */
      dir = -hemisphere(&s, nf, 0.01f);
      inward = true;
    } else if (kind == 2u) { /* diffuse */
      dir = hemisphere(&s, nf, 0.0f);
    }
    float3 origin = spawn_ray_origin(sp.position, sp.p_error, sp.normal, dir);
    if (kind == 3u) { /* shadow ray toward a point light 10 sizes away, as the shade stages make them */
      const float3 light = sp.position + 10.0f * size * hemisphere(&s, nf, 0.0f);
      origin = spawn_ray_origin(sp.position, sp.p_error, sp.normal, nf);
      const float dist = length(light - origin);
      dir = (light - origin) / dist;
      /* A light below the tangent plane as seen from the origin is skipped
       * by the stages (dot(geometric, l) <= 0): the ray would enter. */
      if (!(dot(dir, nf) > 0.0f)) continue;
      tmax = shadow_ray_tmax(dist, dir, (float3)(0.0f), (float3)(0.0f));
    }
    if (!(fabs(origin.x) < 1e30f && fabs(origin.y) < 1e30f && fabs(origin.z) < 1e30f)) ++nonfinite;
    Hit r = hit_none(tmax);
    if (!intersect_prim_ref(spheres, cylinders, triangles, ref, origin, dir, 0.0f, &r)) continue;
    const bool bad = !inward || !closed || (r.u == h.u && r.t * length(dir) < 1e-3f * size);
    if (bad) {
      if (spurious == 0u)
        example[i] = (float4)((float)kind + 10.0f * h.u + 100.0f * r.u, r.t, dot(dir, nf), length(origin - sp.position));
      ++spurious;
    }
  }
  atomic_add(&counts[1], per_hit);
  if (spurious) atomic_add(&counts[2], spurious);
  if (nonfinite) atomic_add(&counts[3], nonfinite);
}
