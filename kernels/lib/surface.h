#line 2 "kernels/lib/surface.h"
/* Turns a Hit into a shading point: an accurate position, the unit geometric
 * and shading normals, texture coordinates and the material index.
 *
 * Rules: the normal always points OUTWARD (out of spheres and cylinders; for
 * triangles along cross(v1 - v0, v2 - v0), i.e. counter-clockwise winding);
 * it is never flipped toward the ray, the shader decides the side. The
 * shading normal equals it except on triangles with vertex normals
 * (HAS_TRIANGLE_SHADING), where it is their barycentric interpolation,
 * normalised and negated if it leaves the geometric normal's hemisphere. The
 * position is rebuilt from the primitive rather than taken as o + t d, whose
 * rounding error grows with t: triangles use the barycentrics, spheres and
 * cylinders are re-projected onto their surface. Only the primitive types
 * enabled by HAS_SPHERES / HAS_CYLINDERS / HAS_TRIANGLES are compiled.
 *
 * Texture coordinates (u, v), v growing upward in the image (texture.h),
 * computed for spheres and cylinders only with HAS_TEXTURES (their atan2 and
 * acos cost more than the rest of the shading; without textures uv = 0):
 *   sphere: n = unit outward normal; u = atan2(n.z, n.x) / 2pi wrapped into
 *     [0, 1) (u = 0 toward +x, 0.25 toward +z: seen from outside with +y up,
 *     u grows to the right); v = acos(-n.y) / pi, 0 at the south pole (-y),
 *     1 at the north pole (+y). At the poles u = 0.
 *   cylinder: a = unit axis; e = the world axis with the smallest |a_i| (the
 *     first of x, y, z on ties); t1 = normalize(cross(a, e)), t2 = cross(a, t1).
 *     side: u = atan2(r.t2, r.t1) / 2pi wrapped into [0, 1) (the angle from t1
 *       toward t2 of the radial vector r), v = (z + half) / (2 half) with z the
 *       axial coordinate: 0 at the bottom rim, 1 at the top rim.
 *     caps (both): planar, u = 0.5 + (p - c).t1 / (2 radius),
 *       v = 0.5 + (p - c).t2 / (2 radius), c the cap's centre.
 *   triangle: the barycentric interpolation of (u0, v0), (u1, v1), (u2, v2)
 *     from TriangleShading with HAS_TRIANGLE_SHADING; without it every
 *     triangle has (0, 0), (1, 0), (0, 1) at v0, v1, v2, so uv = (hit.u, hit.v).
 * triangle_shading is read only with HAS_TRIANGLE_SHADING; otherwise any
 * (dummy) buffer may be passed. */
#ifndef CAUSTICA_LIB_SURFACE_H
#define CAUSTICA_LIB_SURFACE_H

#include "lib/geometry.h"

/* What shading reads of the scene beyond the traversal's geometry: shapes,
 * per-triangle shading data, materials, textures and the environment map
 * (lib/lights/environment_light.h; read only with HAS_ENVIRONMENT). */
#define SCENE_SURFACE_PARAMS                                                                              \
  __global const Sphere *restrict spheres, __global const Cylinder *restrict cylinders,                 \
      __global const Triangle *restrict triangles, __global const TriangleShading *restrict triangle_shading, \
      __global const TriangleTangents *restrict triangle_tangents,                                        \
      __global const TriangleColours *restrict triangle_colours, __global const Material *restrict materials, \
      __global const Texture *restrict textures, __global const ushort *restrict texels,                  \
      __global const float *restrict environment
#define SCENE_SURFACE_ARGS                                                                                  \
  spheres, cylinders, triangles, triangle_shading, triangle_tangents, triangle_colours, materials, textures, texels, \
      environment

typedef struct {
  float3 position;
  float3 normal;         /* geometric, outward */
  float3 shading_normal; /* outward, in the geometric normal's hemisphere */
  float2 uv;
  uint material;
  /* the vertex colours' interpolation (HAS_VERTEX_COLOURS), else 1: set by
   * shading_point_at (lib/shading_point.h) */
  float3 colour;
  /* the clear coat's normal, outward (lib/bsdf.h): the shading normal
   * before any normal map, or the coat's own map (HAS_NORMAL_MAPS) */
  float3 coat_normal;
  /* Per-component bound on the position's distance from the exact surface
   * point it stands for (see spawn_ray_origin, geometry.h): derived from
   * the arithmetic below, so it follows the primitive's size and distance
   * from the origin, not |position|. */
  float3 p_error;
} SurfacePoint;

inline float max_abs3(float3 v) { return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z))); }

/* atan2(y, x) / 2pi in [0, 1). u just below 0 would round to exactly 1 after
 * the + 1, which is the same place as 0 on a tiling texture. x = y = 0 (a
 * pole) gives 0 whatever atan2's fast variant does there. */
inline float angle_unit(float y, float x) {
  if (x == 0.0f && y == 0.0f) return 0.0f;
  float u = atan2(y, x) * (0.5f / M_PI_F);
  if (u < 0.0f) u += 1.0f;
  return u < 1.0f ? u : 0.0f;
}

/* The cylinder's texture frame (see the header): a function of the axis
 * alone, so it is the same for every hit and every device. */
inline void cylinder_uv_frame(float3 a, float3* t1, float3* t2) {
  const float3 m = fabs(a);
  const float3 e = (m.x <= m.y && m.x <= m.z) ? make_float3(1.0f, 0.0f, 0.0f)
                                               : (m.y <= m.z ? make_float3(0.0f, 1.0f, 0.0f) : make_float3(0.0f, 0.0f, 1.0f));
  *t1 = normalize(cross(a, e));
  *t2 = cross(a, *t1);
}

/* Triangle `index`'s texture coordinates at barycentrics (b1, b2), the
 * weights of v1 and v2 (a Hit's u and v): see the header. A triangle
 * light's sampled point reads its emission texture here too
 * (lib/lights/triangle_light.h), so both ways of reaching a point agree. */
inline float2 triangle_uv(__global const TriangleShading* triangle_shading, uint index, float b1, float b2) {
#if HAS_TRIANGLE_SHADING
  __global const TriangleShading* ts = &triangle_shading[index];
  /* Edge form, as the position: tiled UVs (1000.25...) keep their fraction. */
  const float2 uv0 = make_float2(ts->u0, ts->v0);
  return uv0 + b1 * (make_float2(ts->u1, ts->v1) - uv0) + b2 * (make_float2(ts->u2, ts->v2) - uv0);
#else
  (void)triangle_shading;
  (void)index;
  return make_float2(b1, b2);
#endif
}

CS_DEVICE SurfacePoint surface_at(__global const Sphere* spheres, __global const Cylinder* cylinders,
                        __global const Triangle* triangles, __global const TriangleShading* triangle_shading, Hit hit,
                        float3 o, float3 d) {
  /* each read only with its feature flag (HAS_SPHERES, ...) */
  (void)spheres;
  (void)cylinders;
  (void)triangles;
  (void)triangle_shading;
  SurfacePoint sp;
  sp.position = o + hit.t * d;
  sp.normal = make_float3(0.0f, 0.0f, 1.0f);
  sp.uv = make_float2(0.0f, 0.0f);
  sp.material = 0u;
  sp.colour = splat_float3(1.0f);
  sp.p_error = splat_float3(0.0f);
  uint type = prim_ref_type(hit.prim);
  uint index = prim_ref_index(hit.prim);
  (void)type;
  (void)index;
#if HAS_SPHERES
  if (type == PRIM_SPHERE) {
    float4 s = spheres[index].center_radius;
    /* Relative to the centre, so the direction is as exact as the hit. */
    float3 rel = (o - s.xyz) + hit.t * d;
    sp.normal = normalize(rel);
    sp.position = s.xyz + s.w * sp.normal;
    sp.material = spheres[index].material;
    /* r * normalize(rel) is within 5 roundings of the sphere (pbrt's
     * re-projection bound), and adding the centre rounds once more, by at
     * most ulp(position). The roots the sphere test finds from an origin
     * near the surface are good to a few roundings of r: 8, not 5, covers
     * them too. */
    sp.p_error = error_gamma(8.0f) * fabs(s.w * sp.normal) + error_gamma(1.0f) * fabs(sp.position);
#if HAS_TEXTURES
    sp.uv = make_float2(angle_unit(sp.normal.z, sp.normal.x), acos(clamp(-sp.normal.y, -1.0f, 1.0f)) * M_1_PI_F);
#endif
  }
#endif
#if HAS_CYLINDERS
  if (type == PRIM_CYLINDER) {
    float4 cr = cylinders[index].center_radius;
    float3 axis = cylinders[index].axis_half.xyz;
    float half_length = cylinders[index].axis_half.w;
    float3 rel = (o - cr.xyz) + hit.t * d;
    float z = clamp(dot(rel, axis), -half_length, half_length);
    float3 radial = rel - dot(rel, axis) * axis;
#if HAS_TEXTURES
    float3 t1, t2;
    cylinder_uv_frame(axis, &t1, &t2);
#endif
    if (hit.u == CYL_PART_SIDE) {
      float len = length(radial);
      /* A hit exactly on the axis cannot be on the side; any normal
       * perpendicular to the axis is as good as another there. */
      sp.normal = len > 0.0f ? radial / len : normalize(cross(axis, make_float3(axis.y, axis.z, axis.x)));
      sp.position = cr.xyz + z * axis + cr.w * sp.normal;
#if HAS_TEXTURES
      sp.uv = make_float2(angle_unit(dot(sp.normal, t2), dot(sp.normal, t1)),
                       half_length > 0.0f ? (z + half_length) / (2.0f * half_length) : 0.5f);
#endif
    } else {
      float sgn = hit.u == CYL_PART_TOP ? 1.0f : -1.0f;
      sp.normal = sgn * axis;
      /* Clamp onto the disc: a rim hit may land a hair outside. */
      float len = length(radial);
      if (len > cr.w) radial *= cr.w / len;
      sp.position = cr.xyz + (sgn * half_length) * axis + radial;
#if HAS_TEXTURES
      float scale = cr.w > 0.0f ? 0.5f / cr.w : 0.0f;
      sp.uv = make_float2(0.5f + dot(radial, t1) * scale, 0.5f + dot(radial, t2) * scale);
#endif
    }
    sp.material = cylinders[index].material;
    /* centre + z axis + radial: the last two within 7 roundings of their
     * exact values (each at most radius or half the length in size), the
     * two sums one rounding of |position| each. 8 rather than 7 also covers
     * the cylinder test's roots from an origin near the surface, good to a
     * few roundings of |origin - centre| <= radius + half length. */
    sp.p_error = error_gamma(2.0f) * fabs(sp.position) + error_gamma(8.0f) * splat_float3(cr.w + half_length);
  }
#endif
  sp.shading_normal = sp.normal;
#if HAS_TRIANGLES
  if (type == PRIM_TRIANGLE) {
    float3 v0 = triangles[index].v0.xyz;
    float3 v1 = triangles[index].v1.xyz;
    float3 v2 = triangles[index].v2.xyz;
    /* Edge vectors of a small triangle far from the origin are nearly exact;
     * summing weighted absolute positions would not be. */
    sp.position = v0 + hit.u * (v1 - v0) + hit.v * (v2 - v0);
    sp.normal = normalize(cross(v1 - v0, v2 - v0));
    sp.shading_normal = sp.normal;
    sp.material = triangles[index].material;
    /* pbrt's bound for the barycentric reconstruction is gamma(7) times
     * the absolute terms; the second term is ours: pbrt also rejects hits
     * with t below the test's own error bound, which would cost the 4-wide
     * block test in the traversal loop, so instead the offset absorbs that
     * error, a few tens of roundings of the triangle's extent (the sheared
     * vertex depths the test computes t from). That error lies along the
     * new ray, in any direction, so it is the same in every component: a
     * per-component bound would vanish along the normal of an axis-aligned
     * triangle (e1.y = e2.y = 0 on a floor), and the floor got acne. */
    const float3 e1 = v1 - v0, e2 = v2 - v0;
    sp.p_error = error_gamma(7.0f) * (fabs(v0) + fabs(hit.u * e1) + fabs(hit.v * e2)) +
                 splat_float3(error_gamma(32.0f) * (max_abs3(e1) + max_abs3(e2)));
    sp.uv = triangle_uv(triangle_shading, index, hit.u, hit.v);
#if HAS_TRIANGLE_SHADING
    __global const TriangleShading* ts = &triangle_shading[index];
    const float3 n = (1.0f - hit.u - hit.v) * ts->n0.xyz + hit.u * ts->n1.xyz + hit.v * ts->n2.xyz;
    const float n2 = dot(n, n);
    /* Opposite vertex normals can cancel; the geometric normal stands in. */
    if (n2 > 1e-12f) {
      const float3 sn = n * rsqrt(n2);
      sp.shading_normal = dot(sn, sp.normal) < 0.0f ? -sn : sn;
    }
#endif
  }
#endif
  sp.coat_normal = sp.shading_normal;
  return sp;
}

#endif /* CAUSTICA_LIB_SURFACE_H */
