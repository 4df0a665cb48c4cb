#line 2 "kernels/lib/surface.h"
/* Turns a Hit into a shading point: an accurate position, the unit geometric
 * normal and the material index.
 *
 * Rules: the normal always points OUTWARD (out of spheres and cylinders; for
 * triangles along cross(v1 - v0, v2 - v0), i.e. counter-clockwise winding);
 * it is never flipped toward the ray, the shader decides the side. The
 * position is rebuilt from the primitive rather than taken as o + t d, whose
 * rounding error grows with t: triangles use the barycentrics, spheres and
 * cylinders are re-projected onto their surface. Only the primitive types
 * enabled by HAS_SPHERES / HAS_CYLINDERS / HAS_TRIANGLES are compiled. */
#ifndef CAUSTICA_LIB_SURFACE_H
#define CAUSTICA_LIB_SURFACE_H

#include "lib/geometry.h"

typedef struct {
  float3 position;
  float3 normal;
  uint material;
  /* Magnitude of the numbers the position was computed from (|centre| +
   * radius, largest vertex coordinate...). The position's rounding error
   * scales with it, not with |position|: a point near the origin on a
   * sphere of radius 25 centred 25 away carries errors of ulp(25). */
  float error_scale;
} SurfacePoint;

inline float max_abs3(float3 v) { return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z))); }

/* Origin of a secondary ray leaving sp on the side side_normal points to:
 * the ULP offset of offset_ray_origin (which scales with |position|) plus a
 * push of 2^-17 (64 float epsilons) of the error scale along the normal. */
inline float3 spawn_point(SurfacePoint sp, float3 side_normal) {
  return offset_ray_origin(sp.position, side_normal) + side_normal * (sp.error_scale * 0x1.0p-17f);
}

SurfacePoint surface_at(__global const Sphere* spheres, __global const Cylinder* cylinders,
                        __global const Triangle* triangles, Hit hit, float3 o, float3 d) {
  SurfacePoint sp;
  sp.position = o + hit.t * d;
  sp.normal = (float3)(0.0f, 0.0f, 1.0f);
  sp.material = 0u;
  sp.error_scale = 0.0f;
  uint type = prim_ref_type(hit.prim);
  uint index = prim_ref_index(hit.prim);
#ifdef HAS_SPHERES
  if (type == PRIM_SPHERE) {
    float4 s = spheres[index].center_radius;
    /* Relative to the centre, so the direction is as exact as the hit. */
    float3 rel = (o - s.xyz) + hit.t * d;
    sp.normal = normalize(rel);
    sp.position = s.xyz + s.w * sp.normal;
    sp.material = spheres[index].material;
    sp.error_scale = max_abs3(s.xyz) + s.w;
  }
#endif
#ifdef HAS_CYLINDERS
  if (type == PRIM_CYLINDER) {
    float4 cr = cylinders[index].center_radius;
    float3 axis = cylinders[index].axis_half.xyz;
    float half_length = cylinders[index].axis_half.w;
    float3 rel = (o - cr.xyz) + hit.t * d;
    float z = clamp(dot(rel, axis), -half_length, half_length);
    float3 radial = rel - dot(rel, axis) * axis;
    if (hit.u == CYL_PART_SIDE) {
      float len = length(radial);
      /* A hit exactly on the axis cannot be on the side; any normal
       * perpendicular to the axis is as good as another there. */
      sp.normal = len > 0.0f ? radial / len : normalize(cross(axis, (float3)(axis.y, axis.z, axis.x)));
      sp.position = cr.xyz + z * axis + cr.w * sp.normal;
    } else {
      float sgn = hit.u == CYL_PART_TOP ? 1.0f : -1.0f;
      sp.normal = sgn * axis;
      /* Clamp onto the disc: a rim hit may land a hair outside. */
      float len = length(radial);
      if (len > cr.w) radial *= cr.w / len;
      sp.position = cr.xyz + (sgn * half_length) * axis + radial;
    }
    sp.material = cylinders[index].material;
    sp.error_scale = max_abs3(cr.xyz) + cr.w + half_length;
  }
#endif
#ifdef HAS_TRIANGLES
  if (type == PRIM_TRIANGLE) {
    float3 v0 = triangles[index].v0.xyz;
    float3 v1 = triangles[index].v1.xyz;
    float3 v2 = triangles[index].v2.xyz;
    /* Edge vectors of a small triangle far from the origin are nearly exact;
     * summing weighted absolute positions would not be. */
    sp.position = v0 + hit.u * (v1 - v0) + hit.v * (v2 - v0);
    sp.normal = normalize(cross(v1 - v0, v2 - v0));
    sp.material = triangles[index].material;
    sp.error_scale = fmax(max_abs3(v0), fmax(max_abs3(v1), max_abs3(v2)));
  }
#endif
  return sp;
}

#endif /* CAUSTICA_LIB_SURFACE_H */
