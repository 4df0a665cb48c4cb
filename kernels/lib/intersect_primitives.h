#line 2 "kernels/lib/intersect_primitives.h"
/* Ray/primitive tests. Each takes the ray (o, d, tmin) and an in/out *t that
 * holds tmax on input; it returns true and lowers *t only for a hit with
 * tmin < t < *t. t is in units of d (d need not be normalised).
 *
 * Rules: float32, finite values only (see geometry.h); every test works in
 * coordinates relative to the primitive so that precision follows the
 * primitive's size, not its distance from the world origin; quadratics avoid
 * the cancellation of the textbook formula, so a ray from far away still
 * gets a t with relative accuracy. Surfaces are closed: an origin inside a
 * sphere or cylinder hits the far side. */
#ifndef CAUSTICA_LIB_INTERSECT_PRIMITIVES_H
#define CAUSTICA_LIB_INTERSECT_PRIMITIVES_H

#include "lib/geometry.h"

/* The triangle edge functions must be evaluated the same way for both
 * triangles sharing an edge; a contracted a*b - c*d is not antisymmetric.
 * Under -cl-fast-relaxed-math, clang may also reassociate, and would do so
 * differently in the scalar test and the 4-wide block test, which must agree
 * bit for bit (traversal vs brute force, neighbours on a shared edge):
 * precise semantics for this file only, the kernels around it stay fast.
 * Both switched back at the end of this file. */
#ifdef __OPENCL_C_VERSION__
#pragma float_control(precise, on, push)
#pragma OPENCL FP_CONTRACT OFF
#endif /* the host builds this without contraction (-ffp-contract=off) */

#if HAS_TRIANGLES && defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define CAUSTICA_EDGE_FP64 1
#elif HAS_TRIANGLES && !defined(__OPENCL_C_VERSION__)
#define CAUSTICA_EDGE_FP64 1 /* the host has double, as every device that reports fp64 */
#endif

/* Accepts t inside the open interval (tmin, *tbest). */
CS_DEVICE bool accept_root(float t, float tmin, float* tbest) {
  if (t > tmin && t < *tbest) {
    *tbest = t;
    return true;
  }
  return false;
}

/* Roots of a s^2 + 2 b s + c = 0 (a > 0) as (near, far); false without real
 * roots. The discriminant is passed in because callers compute it in a
 * cancellation-free form. q takes the sign of b so that no root is formed as
 * the difference of two nearly equal numbers. */
CS_DEVICE bool solve_quadratic(float a, float b, float c, float disc, float* s0, float* s1) {
  if (disc < 0.0f) return false;
  float q = -(b + copysign(sqrt(disc), b));
  float r0 = q / a;
  float r1 = q != 0.0f ? c / q : r0;
  *s0 = fmin(r0, r1);
  *s1 = fmax(r0, r1);
  return true;
}

CS_DEVICE bool intersect_sphere(float3 center, float radius, float3 o, float3 d, float tmin, float* t) {
  float3 f = o - center;
  float a = dot(d, d);
  float b = dot(f, d);
  /* r^2 - |perpendicular from the centre to the line|^2, scaled by a: its
   * error grows like r |f| eps, where b^2 - a c would lose |f|^2 eps. */
  float3 perp = f - (b / a) * d;
  float disc = a * (radius * radius - dot(perp, perp));
  float c = dot(f, f) - radius * radius;
  float t0, t1;
  if (!solve_quadratic(a, b, c, disc, &t0, &t1)) return false;
  return accept_root(t0, tmin, t) || accept_root(t1, tmin, t);
}

/* Finite cylinder with both caps. part receives CYL_PART_* of the hit. */
CS_DEVICE bool intersect_cylinder(float3 center, float3 axis, float radius, float half_length, float3 o, float3 d,
                        float tmin, float* t, float* part) {
  float3 f = o - center;
  float fz = dot(f, axis);
  float dz = dot(d, axis);
  float3 fp = f - fz * axis; /* components perpendicular to the axis */
  float3 dp = d - dz * axis;
  float a = dot(dp, dp);
  float dd = dot(d, d);
  bool hit = false;

  /* An origin outside the infinite cylinder that moves away from its axis
   * never meets the side: both roots are negative. The re-solved roots
   * below do not keep that sign when the closest point to the axis is far
   * behind the origin (a ray leaving the side nearly along the axis, tc of
   * 10^5 sizes): their difference tc + s then re-hit the side at t ~ 10^4
   * (1 in 5 million rays at scale 1e4, tests/stiff/test_self_intersection).
   * The signs of c and b at the origin are exact enough for any origin
   * spawned off the surface by its error bound. */
  const bool leaving_side = dot(fp, fp) > radius * radius && dot(fp, dp) >= 0.0f;
  if (!leaving_side && a > 1e-12f * dd) {
    /* Re-solve from the ray point closest to the axis: there the quadratic's
     * coefficients are of the cylinder's size, so the roots keep their
     * precision however far the origin is. */
    float tc = -dot(fp, dp) / a;
    float3 g = fp + tc * dp;
    float zc = fz + tc * dz;
    float b = dot(g, dp);
    float c = dot(g, g) - radius * radius;
    float3 perp = g - (b / a) * dp;
    float disc = a * (radius * radius - dot(perp, perp));
    float s0, s1;
    if (solve_quadratic(a, b, c, disc, &s0, &s1)) {
      if (fabs(zc + s0 * dz) <= half_length && accept_root(tc + s0, tmin, t)) {
        *part = CYL_PART_SIDE;
        hit = true;
      } else if (fabs(zc + s1 * dz) <= half_length && accept_root(tc + s1, tmin, t)) {
        *part = CYL_PART_SIDE;
        hit = true;
      }
    }
  }

  /* A ray (nearly) parallel to the caps' plane meets them only beyond any
   * sensible t; skipping it keeps t finite. */
  if (dz * dz > 1e-24f * dd) {
    float r2 = radius * radius;
    float t_top = (half_length - fz) / dz;
    float3 p_top = fp + t_top * dp;
    if (dot(p_top, p_top) <= r2 && accept_root(t_top, tmin, t)) {
      *part = CYL_PART_TOP;
      hit = true;
    }
    float t_bottom = (-half_length - fz) / dz;
    float3 p_bottom = fp + t_bottom * dp;
    if (dot(p_bottom, p_bottom) <= r2 && accept_root(t_bottom, tmin, t)) {
      *part = CYL_PART_BOTTOM;
      hit = true;
    }
  }
  return hit;
}

/* Watertight ray/triangle test (Woop, Benthin & Wald 2013): vertices are
 * sheared into a space where the ray is the +z axis through (0,0), and the
 * 2D edge functions decide coverage. A shared edge yields the same edge
 * function with opposite sign in both triangles, so a ray never slips
 * between them; a ray exactly on an edge hits both. */
CS_DEVICE float3 shear_vertex(float3 v, float3 o, int kx, int ky, int kz, float3 shear) {
  float3 a = v - o;
  float ax = kx == 0 ? a.x : (kx == 1 ? a.y : a.z);
  float ay = ky == 0 ? a.x : (ky == 1 ? a.y : a.z);
  float az = kz == 0 ? a.x : (kz == 1 ? a.y : a.z);
  return make_float3(ax - shear.x * az, ay - shear.y * az, shear.z * az);
}

CS_DEVICE float edge_function(float2 p, float2 q) {
  float e = p.x * q.y - p.y * q.x;
#ifdef CAUSTICA_EDGE_FP64
  /* Rounded to zero or too small to trust its sign: products of floats are
   * exact in double, so the sign there is the exact one. */
  float bound = 2.5e-7f * (fabs(p.x * q.y) + fabs(p.y * q.x));
  if (fabs(e) <= bound) e = (float)((double)p.x * (double)q.y - (double)p.y * (double)q.x);
#endif
  return e;
}

CS_DEVICE bool intersect_triangle(float3 v0, float3 v1, float3 v2, float3 o, float3 d, float tmin, float* t, float* u,
                        float* v) {
  float3 ad = fabs(d);
  int kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float dkz = kz == 0 ? d.x : (kz == 1 ? d.y : d.z);
  if (dkz < 0.0f) { /* keep the winding of the sheared triangle */
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  float dkx = kx == 0 ? d.x : (kx == 1 ? d.y : d.z);
  float dky = ky == 0 ? d.x : (ky == 1 ? d.y : d.z);
  float3 shear = make_float3(dkx / dkz, dky / dkz, 1.0f / dkz);

  float3 a = shear_vertex(v0, o, kx, ky, kz, shear);
  float3 b = shear_vertex(v1, o, kx, ky, kz, shear);
  float3 c = shear_vertex(v2, o, kx, ky, kz, shear);
  float e0 = edge_function(c.xy, b.xy); /* weight of v0 */
  float e1 = edge_function(a.xy, c.xy); /* weight of v1 */
  float e2 = edge_function(b.xy, a.xy); /* weight of v2 */
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return false;
  float det = e0 + e1 + e2;
  if (det == 0.0f) return false; /* ray in the triangle's plane, or degenerate */
  float inv = 1.0f / det;
  float th = (e0 * a.z + e1 * b.z + e2 * c.z) * inv;
  if (!accept_root(th, tmin, t)) return false;
  *u = e1 * inv;
  *v = e2 * inv;
  return true;
}

/* The per-ray half of intersect_triangle (shear axes and constants), shared
 * by every triangle block the ray meets. */
typedef struct {
  float ox, oy, oz; /* origin along kx, ky, kz */
  float sx, sy, sz; /* shear */
  int kx, ky, kz;
} TriangleRay;

CS_DEVICE TriangleRay triangle_ray(float3 o, float3 d) {
  TriangleRay r;
  float3 ad = fabs(d);
  int kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float4 d4 = make_float4_xyz(d, 1.0f);
  /* One variable shuffle gathers the three permuted components (the same
   * values as selecting them one by one, in far fewer instructions). */
  float dkz = shuffle(d4, splat_uint4(kz)).x;
  if (dkz < 0.0f) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  const uint4 perm = make_uint4(kx, ky, 3, kz);
  const float4 dp = shuffle(d4, perm);                  /* dkx, dky, 1, dkz */
  const float4 op = shuffle(make_float4_xyz(o, 0.0f), perm);   /* okx, oky, 0, okz */
  const float4 shear = dp / splat_float4(dkz);              /* dkx/dkz, dky/dkz, 1/dkz, 1 */
  r.sx = shear.x;
  r.sy = shear.y;
  r.sz = shear.z;
  r.ox = op.x;
  r.oy = op.y;
  r.oz = op.w;
  r.kx = kx;
  r.ky = ky;
  r.kz = kz;
  return r;
}

/* any() on a compare mask, as a byte-narrowed movemask: PoCL's any()
 * extracts and tests the lanes one by one. */
CS_DEVICE bool any4(int4 mask) { return as_uint(convert_char4(mask)) != 0u; }

/* edge_function on four lanes, without its fp64 re-evaluation: *unsure
 * receives the lanes whose sign it would re-evaluate (see edge_exact4). */
CS_DEVICE float4 edge_function4(float4 px, float4 py, float4 qx, float4 qy, int4* unsure) {
  float4 l = px * qy, r = py * qx;
  float4 e = l - r;
  *unsure = fabs(e) <= 2.5e-7f * (fabs(l) + fabs(r));
  return e;
}

/* The re-evaluation, done only when some lane of some edge needs it, so that
 * the common case pays one test for all three edges. */
CS_DEVICE float4 edge_exact4(float4 e, float4 px, float4 py, float4 qx, float4 qy, int4 unsure) {
#ifdef CAUSTICA_EDGE_FP64
  double4 exact = convert_double4(px) * convert_double4(qy) - convert_double4(py) * convert_double4(qx);
  e = select(e, convert_float4(exact), unsure);
#endif
  return e;
}

/* intersect_triangle on the four lanes of a block at once, operation for
 * operation the same (so a lane agrees with the scalar test bit for bit,
 * shared edges included). The axes are picked per ray by row offset, which
 * is why the block stores each vertex coordinate as its own row. Returns -1
 * in the lanes hit with tmin < t < tmax, and their t, u, v. */
CS_DEVICE __attribute__((always_inline)) int4 intersect_triangle_block(__global const TriangleBlock4* block,
                                                             const TriangleRay* r, float tmin, float tmax, float4* t,
                                                             float4* u, float4* v) {
  __global const float4* p = (__global const float4*)block; /* 16-byte aligned rows */
  float4 az = p[r->kz] - r->oz;
  float4 bz = p[3 + r->kz] - r->oz;
  float4 cz = p[6 + r->kz] - r->oz;
  float4 ax = (p[r->kx] - r->ox) - r->sx * az;
  float4 ay = (p[r->ky] - r->oy) - r->sy * az;
  float4 bx = (p[3 + r->kx] - r->ox) - r->sx * bz;
  float4 by = (p[3 + r->ky] - r->oy) - r->sy * bz;
  float4 cx = (p[6 + r->kx] - r->ox) - r->sx * cz;
  float4 cy = (p[6 + r->ky] - r->oy) - r->sy * cz;
  int4 u0, u1, u2;
  float4 e0 = edge_function4(cx, cy, bx, by, &u0);
  float4 e1 = edge_function4(ax, ay, cx, cy, &u1);
  float4 e2 = edge_function4(bx, by, ax, ay, &u2);
#ifdef CAUSTICA_EDGE_FP64
  if (any4(u0 | u1 | u2)) {
    e0 = edge_exact4(e0, cx, cy, bx, by, u0);
    e1 = edge_exact4(e1, ax, ay, cx, cy, u1);
    e2 = edge_exact4(e2, bx, by, ax, ay, u2);
  }
#endif
  int4 outside = ((e0 < 0.0f) | (e1 < 0.0f) | (e2 < 0.0f)) & ((e0 > 0.0f) | (e1 > 0.0f) | (e2 > 0.0f));
  float4 det = e0 + e1 + e2;
  int4 hit = ~outside & (det != 0.0f);
  if (!any4(hit)) return hit;
  /* No 1/0 even in lanes that are dropped: fast-relaxed-math assumes no inf. */
  float4 inv = 1.0f / select(det, splat_float4(1.0f), det == 0.0f);
  float4 th = (e0 * (r->sz * az) + e1 * (r->sz * bz) + e2 * (r->sz * cz)) * inv;
  hit &= (th > tmin) & (th < tmax);
  *t = th;
  *u = e1 * inv;
  *v = e2 * inv;
  return hit;
}

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT ON
#pragma float_control(pop)
#endif

#endif /* CAUSTICA_LIB_INTERSECT_PRIMITIVES_H */
