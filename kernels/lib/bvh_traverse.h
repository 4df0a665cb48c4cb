#line 2 "kernels/lib/bvh_traverse.h"
/* Closest-hit and any-hit queries over the 8-wide BVH of types.h (BvhNode8,
 * TriangleBlock4; host/accel/bvh_wide.cpp builds it).
 *
 * Why this shape: PoCL runs a work-group as a loop over its work-items and
 * does not vectorise that loop across them when its body is a traversal, so
 * the SIMD width has to live inside one work-item. One float8 slab test
 * checks all eight children of a node, one float4 watertight test four
 * triangles of a leaf. Children are visited nearest first from a stack kept
 * sorted by entry distance, entries beyond the closest hit are dropped when
 * popped, and a node with a single child hit descends without the stack.
 * trace_any uses no distances: it takes a node's highest hit lane and pushes
 * the others so that they pop from the highest lane down. For shadow rays
 * that finds an occluder after fewer leaves than lowest lane first or
 * nearest first, and after fewer nodes than lowest lane first, in every
 * bench scene and in both directions along the same segments (occluded
 * shadow rays, nodes and leaves a ray, lowest lane -> highest lane: bunny
 * 9.65 -> 7.54 and 5.18 -> 2.95, Sponza 9.51 -> 7.99 and 2.12 -> 1.64,
 * Conference 5.54 -> 4.54 and 2.64 -> 1.99; docs/performance.md), for one
 * clz instead of one tzcnt. Unoccluded rays visit the same nodes in any order.
 *
 * Rules: finite arithmetic only (programs may use -cl-fast-relaxed-math):
 * reciprocal directions are clamped to +-BVH_INV_DIR_MAX; empty slots are
 * boxes lo = +1e18, hi = -1e18, which the slab test rejects because it picks
 * near/far planes by the direction's sign rather than by min/max. The
 * stack holds BVH_STACK_SIZE entries: a node pushes its hit children one by
 * one only while that leaves room for the levels below it (its `height`);
 * otherwise it pushes a single "group" entry (itself, restricted to those
 * children) that is re-tested when popped. The collapse keeps the root's
 * height below BVH_STACK_SIZE, so the stack never overflows. Primitive code
 * is compiled only for the types the scene has (HAS_SPHERES, HAS_CYLINDERS,
 * HAS_TRIANGLES).
 *
 * Stack bound, in full: the wide BVH's collapse throws unless the root's
 * height (levels of nodes, leaves not counted) is below BVH_STACK_SIZE
 * (host/accel/bvh_wide.cpp; the binary build it collapses is limited to
 * that many levels too, host/accel/bvh.h). Invariant: on reaching a node,
 * sp + node->height <= BVH_STACK_SIZE - 1. It holds at the root (sp = 0).
 * Descending to one child keeps sp; pushing one entry (the two-child case,
 * a group entry) adds 1 and the child is at least one level lower; pushing
 * k - 1 sorted children is allowed only when sp + k + height <=
 * BVH_STACK_SIZE + 1, which is the invariant for the child taken; a child
 * popped later sits below where its node's entries started, and a group
 * entry re-tests its node at the sp it was pushed from. Leaves push
 * nothing. So sp < BVH_STACK_SIZE at every push, whatever the ray: the
 * bound uses heights only, no distances, and holds for NaN rays too.
 *
 * Degenerate rays (the traversal's domain, ray_traceable): a NaN or
 * infinite component, a zero direction, a direction whose largest
 * component is outside [1 / BVH_INV_DIR_MAX, BVH_INV_DIR_MAX], or an origin
 * coordinate beyond BVH_ORIGIN_MAX. Such rays miss (trace_any: unoccluded)
 * without a node visited. Why: with NaN or infinite plane distances the
 * slab test accepts lanes it must reject (max8/min8 drop a NaN operand, and
 * an infinite direction makes every slope 0), and that includes empty
 * slots, whose child WIDE_CHILD_EMPTY reads as a leaf of 8 primitives at
 * index 0x07FFFFFF: out of bounds, a segfault in PoCL. Inside the domain
 * every slope and offset of wide_ray is finite (|o * inv_d| <= 1e38), so no
 * plane distance is NaN and an empty slot's near plane (1e18 * |inv_d|
 * >= 1 from its far one) always lies beyond its far plane. The check is
 * integer tests on the input bits (-cl-fast-relaxed-math may fold isnan
 * and isinf to false) and costs one branch per ray. */
#ifndef CAUSTICA_LIB_BVH_TRAVERSE_H
#define CAUSTICA_LIB_BVH_TRAVERSE_H

#include "lib/alpha_cutout.h"
#include "lib/geometry.h"
#include "lib/intersect_primitives.h"

#ifndef BVH_STACK_SIZE /* tests shrink it to exercise the group entries */
#define BVH_STACK_SIZE CS_BVH_STACK_SIZE
#endif
/* BVH_INV_DIR_MAX and BVH_EXIT_SLACK: shared/types.h. The exit slack also
 * covers the approximate reciprocals fast-relaxed-math may use. */
/* The slab distances are fma(plane, inv_d, -o * inv_d): one operation per
 * plane instead of (plane - o) * inv_d, but -o * inv_d carries a rounding
 * error relative to |o * inv_d|, not to t. Near planes move that much
 * earlier and far planes later (4x the half-ulp bound), per axis. */
#define BVH_PLANE_ERROR 0x1.0p-22f
/* A set of child lanes. On x86 CPUs one bit per lane, straight from the
 * compare (movmskps), with the lowest lane by tzcnt: this is the path from a
 * node's boxes to its child's address, paid at every node, and it is several
 * cycles shorter than byte lanes (5-20% more rays/s on the bench scenes).
 * Tests force the portable form with -DBVH8_PORTABLE_LANES. */
#if defined(__OPENCL_C_VERSION__) && defined(__x86_64__) && defined(__AVX__) && !defined(BVH8_PORTABLE_LANES)
typedef uint Lanes;
#define BVH8_LANES 0xFFu
CS_DEVICE Lanes bvh8_lanes_hit(int8 hit) {
  typedef float v8sf __attribute__((vector_size(32)));
  return (uint)__builtin_ia32_movmskps256((v8sf)as_float8(hit));
}
CS_DEVICE uint bvh8_lane(Lanes lanes) { return (uint)__builtin_ctz(lanes); }
CS_DEVICE uint bvh8_last_lane(Lanes lanes) { return 31u - clz(lanes); }
CS_DEVICE Lanes bvh8_lanes_of_mask(uint mask) { return mask; }
CS_DEVICE Lanes bvh8_without_lane(Lanes lanes, uint lane) { return lanes ^ (1u << lane); }
#else
/* Elsewhere: a compare mask narrowed to bytes and read as one ulong, which
 * PoCL compiles to far less than an OR-reduction (bit 8 * lane). */
typedef ulong Lanes;
#define BVH8_LANES 0x0101010101010101UL
CS_DEVICE Lanes bvh8_lanes_hit(int8 hit) { return as_ulong(convert_char8(hit)) & BVH8_LANES; }
CS_DEVICE uint bvh8_lane(Lanes lanes) { return (uint)(popcount((lanes & (~lanes + 1UL)) - 1UL) >> 3); }
CS_DEVICE uint bvh8_last_lane(Lanes lanes) { return (uint)(63 - clz(lanes)) >> 3; }
CS_DEVICE Lanes bvh8_lanes_of_mask(uint mask) {
  Lanes lanes = 0;
  for (uint i = 0; i < 8; ++i)
    if (mask & (1u << i)) lanes |= 1UL << (8 * i);
  return lanes;
}
CS_DEVICE Lanes bvh8_without_lane(Lanes lanes, uint lane) { return lanes ^ (1UL << (8u * lane)); }
#endif

#ifdef CAUSTICA_CPU_PREFETCH
/* Children pushed for later are fetched now, all their cache lines, so that
 * popping them finds them in cache (Embree does the same); the host defines
 * CAUSTICA_CPU_PREFETCH for CPU devices. OpenCL's prefetch() is a no-op in
 * PoCL, hence clang's builtin; it takes a generic pointer, which OpenCL 1.2
 * cannot convert from __global, so the address goes through an integer:
 * valid where all address spaces are one, as on CPUs. */
#define BVH_PREFETCH_AT(p, offset) __builtin_prefetch((const void*)((ulong)(p) + (offset)))
/* Every cache line of the `bytes` (129..256) from p, aligned or not. */
#define BVH_PREFETCH(p, bytes)          \
  do {                                  \
    BVH_PREFETCH_AT(p, 0);              \
    BVH_PREFETCH_AT(p, 64);             \
    BVH_PREFETCH_AT(p, 128);            \
    BVH_PREFETCH_AT(p, (bytes) - 1);    \
  } while (0)
#else
#define BVH_PREFETCH(p, bytes) ((void)0)
#endif

/* The node or leaf blocks a stack item will visit, fetched ahead. */
CS_DEVICE void bvh8_prefetch_item(__global const BvhNode8* nodes, __global const TriangleBlock4* blocks, uint item) {
  (void)nodes; /* used only where the prefetch is compiled */
  (void)blocks;
  if ((item & WIDE_LEAF_FLAG) == 0) BVH_PREFETCH(&nodes[item], sizeof(BvhNode8));
#if HAS_TRIANGLES
  else if (!(item & WIDE_LEAF_PRIMS)) BVH_PREFETCH(&blocks[item & WIDE_LEAF_INDEX_MASK], sizeof(TriangleBlock4));
#endif
}

/* Tests one primitive (encoded ref) and, on a nearer hit, overwrites *hit. */
CS_DEVICE bool intersect_prim_ref(__global const Sphere* spheres, __global const Cylinder* cylinders,
                        __global const Triangle* triangles, uint ref, float3 o, float3 d, float tmin, Hit* hit) {
  uint type = prim_ref_type(ref);
  uint index = prim_ref_index(ref);
#if HAS_SPHERES
  if (type == PRIM_SPHERE) {
    float4 s = spheres[index].center_radius;
    if (!intersect_sphere(s.xyz, s.w, o, d, tmin, &hit->t)) return false;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->prim = ref;
    return true;
  }
#endif
#if HAS_CYLINDERS
  if (type == PRIM_CYLINDER) {
    float4 cr = cylinders[index].center_radius;
    float4 ah = cylinders[index].axis_half;
    float t = hit->t, part = 0.0f;
    if (!intersect_cylinder(cr.xyz, ah.xyz, cr.w, ah.w, o, d, tmin, &t, &part)) return false;
    hit->t = t;
    hit->u = part;
    hit->v = dot(o - cr.xyz, ah.xyz) + t * dot(d, ah.xyz);
    hit->prim = ref;
    return true;
  }
#endif
#if HAS_TRIANGLES
  if (type == PRIM_TRIANGLE) {
    float t = hit->t, u = 0.0f, v = 0.0f;
    if (!intersect_triangle(triangles[index].v0.xyz, triangles[index].v1.xyz, triangles[index].v2.xyz, o, d,
                            tmin, &t, &u, &v))
      return false;
    hit->t = t;
    hit->u = u;
    hit->v = v;
    hit->prim = ref;
    return true;
  }
#endif
  return false;
}

/* The nearest lane of a triangle block hit nearer than hit->t replaces *hit
 * (with HAS_ALPHA_CUTOUTS, the nearest that alpha keeps: lib/alpha_cutout.h). */
CS_DEVICE __attribute__((always_inline)) void triangle_block_closest(__global const TriangleBlock4* block,
                                                          const TriangleRay* r, float tmin, Hit* hit,
                                                          __global const TriangleAlpha* triangle_alpha,
                                                          __global const ushort* alpha_texels, float3 o, float3 d) {
  float4 t, u, v;
  int4 lanes = intersect_triangle_block(block, r, tmin, hit->t, &t, &u, &v);
  if (!any4(lanes)) return;
#if HAS_ALPHA_CUTOUTS
  lanes = alpha_kept_lanes(block, lanes, u, v, triangle_alpha, alpha_texels, o, d);
  if (!any4(lanes)) return;
#else
  (void)triangle_alpha;
  (void)alpha_texels;
  (void)o;
  (void)d;
#endif
  t = select(splat_float4(hit->t), t, lanes);
  /* Plain compares, not fmin: t is never NaN here. */
  const float t01 = t.y < t.x ? t.y : t.x, t23 = t.w < t.z ? t.w : t.z;
  const int l01 = t.y < t.x ? 1 : 0, l23 = t.w < t.z ? 3 : 2;
  const int lane = t23 < t01 ? l23 : l01;
  float tu[4], tv[4];
  vstore4(u, 0, tu);
  vstore4(v, 0, tv);
  hit->t = t23 < t01 ? t23 : t01;
  hit->u = tu[lane];
  hit->v = tv[lane];
  hit->prim = block->ref[lane];
}

/* The traversal's domain (see the top of this file). */
inline bool ray_traceable(float3 o, float3 d) {
  const uint e = 0x7F800000u; /* exponent all ones: infinite or NaN */
  if (((as_uint(o.x) & e) == e) | ((as_uint(o.y) & e) == e) | ((as_uint(o.z) & e) == e) |
      ((as_uint(d.x) & e) == e) | ((as_uint(d.y) & e) == e) | ((as_uint(d.z) & e) == e))
    return false;
  const float3 ad = fabs(d), ao = fabs(o);
  const float d_max = fmax(ad.x, fmax(ad.y, ad.z)), o_max = fmax(ao.x, fmax(ao.y, ao.z));
  return d_max >= 1.0f / BVH_INV_DIR_MAX && d_max <= BVH_INV_DIR_MAX && o_max <= BVH_ORIGIN_MAX;
}

typedef struct {
  float3 inv_d;   /* clamped reciprocal direction */
  float3 c_near;  /* -o * inv_d - its rounding bound: offset of the near planes */
  float3 inv_far; /* inv_d and -o * inv_d + its rounding bound, both scaled */
  float3 c_far;   /* by 1 + BVH_EXIT_SLACK: the far planes' slope and offset */
  int near_x, near_y, near_z; /* BvhNode8 rows of the near planes (lo or hi by sign) */
  int far_x, far_y, far_z;
  float tmin;
} WideRay;

CS_DEVICE WideRay wide_ray(float3 o, float3 d, float tmin) {
  WideRay r;
  float3 safe = select(d, copysign(splat_float3(1.0f / BVH_INV_DIR_MAX), d), fabs(d) < 1.0f / BVH_INV_DIR_MAX);
  r.inv_d = clamp(1.0f / safe, -BVH_INV_DIR_MAX, BVH_INV_DIR_MAX);
  float3 oi = o * r.inv_d;
  float3 err = fabs(oi) * BVH_PLANE_ERROR;
  r.c_near = -oi - err;
  r.inv_far = r.inv_d * (1.0f + BVH_EXIT_SLACK);
  r.c_far = (-oi + err) * (1.0f + BVH_EXIT_SLACK);
  r.near_x = r.inv_d.x < 0.0f ? 1 : 0;
  r.near_y = r.inv_d.y < 0.0f ? 3 : 2;
  r.near_z = r.inv_d.z < 0.0f ? 5 : 4;
  r.far_x = r.near_x ^ 1;
  r.far_y = r.near_y ^ 1;
  r.far_z = r.near_z ^ 1;
  r.tmin = tmin;
  return r;
}

/* fmax/fmin must honour NaN operands, which costs a compare and a blend
 * per use; these values are never NaN, and this form is a single max/min
 * instruction. */
CS_DEVICE float8 max8(float8 a, float8 b) { return select(b, a, a > b); }
CS_DEVICE float8 min8(float8 a, float8 b) { return select(b, a, a < b); }

/* Slab test of all eight children against [tmin, tmax]: returns the hit
 * lanes (Lanes) and their entry distances in *entry. */
CS_DEVICE Lanes bvh8_test(__global const BvhNode8* node, const WideRay* r, float tmax, float8* entry) {
  /* Rows are 32-byte aligned float8s (256-byte nodes); indexing them as such
   * gives one load each, where vload8 at a variable offset gives two. */
  __global const float8* rows = (__global const float8*)node;
  float8 nx = fma(rows[r->near_x], splat_float8(r->inv_d.x), splat_float8(r->c_near.x));
  float8 ny = fma(rows[r->near_y], splat_float8(r->inv_d.y), splat_float8(r->c_near.y));
  float8 nz = fma(rows[r->near_z], splat_float8(r->inv_d.z), splat_float8(r->c_near.z));
  float8 fx = fma(rows[r->far_x], splat_float8(r->inv_far.x), splat_float8(r->c_far.x));
  float8 fy = fma(rows[r->far_y], splat_float8(r->inv_far.y), splat_float8(r->c_far.y));
  float8 fz = fma(rows[r->far_z], splat_float8(r->inv_far.z), splat_float8(r->c_far.z));
  float8 t_enter = max8(max8(nx, ny), max8(nz, splat_float8(r->tmin)));
  /* Two levels of min on each side, not three: this test is on the
   * critical path from one node to the next. */
  float8 t_exit = min8(min8(fx, fy), min8(fz, splat_float8(tmax)));
  *entry = t_enter;
  return bvh8_lanes_hit(t_enter <= t_exit);
}

CS_DEVICE float entry_lane(float8 e, uint lane) {
  float d[8];
  vstore8(e, 0, d);
  return d[lane];
}

/* The rare case where pushing every hit child of `node` could overrun the
 * stack: pushes one group entry for all of them but the nearest (at the
 * distance of the next nearest) and returns the nearest child. */
CS_DEVICE uint bvh8_push_group(__global const BvhNode8* node, uint node_index, Lanes lanes, const float* dist,
                     uint* stack_item, float* stack_entry, int* sp) {
  uint nearest = bvh8_lane(lanes);
  for (Lanes m = lanes & (lanes - 1); m != 0; m &= m - 1)
    if (dist[bvh8_lane(m)] < dist[nearest]) nearest = bvh8_lane(m);
  uint rest = 0;
  float rest_entry = RAY_T_FAR;
  for (Lanes m = lanes; m != 0; m &= m - 1) {
    uint lane = bvh8_lane(m);
    if (lane == nearest) continue;
    rest |= 1u << lane;
    rest_entry = fmin(rest_entry, dist[lane]);
  }
  stack_item[*sp] = WIDE_GROUP_FLAG | (rest << WIDE_GROUP_MASK_SHIFT) | node_index;
  stack_entry[*sp] = rest_entry;
  ++*sp;
  return node->child[nearest];
}

/* A popped stack item: a group entry becomes its node and lane set. */
CS_DEVICE uint bvh8_unpack(uint item, Lanes* lanes) {
  if ((item & (WIDE_LEAF_FLAG | WIDE_GROUP_FLAG)) != WIDE_GROUP_FLAG) return item;
  *lanes = bvh8_lanes_of_mask((item >> WIDE_GROUP_MASK_SHIFT) & 0xFFu);
  return item & WIDE_NODE_INDEX_MASK;
}

CS_DEVICE uint wide_leaf_count(uint item) { return ((item >> WIDE_LEAF_COUNT_SHIFT) & (WIDE_LEAF_MAX_COUNT - 1u)) + 1u; }

CS_DEVICE Hit trace_closest(SCENE_GEOMETRY_PARAMS, float3 o, float3 d, float tmin, float tmax) {
  (void)triangle_alpha; /* read only with HAS_ALPHA_CUTOUTS and triangles */
  (void)alpha_texels;
  Hit hit = hit_none(tmax);
  if (!ray_traceable(o, d)) return hit;
  const WideRay ray = wide_ray(o, d, tmin);
#if HAS_TRIANGLES
  /* Set up at the first triangle leaf: rays that reach none skip it. */
  TriangleRay tri;
  bool tri_ready = false;
#endif
  uint stack_item[BVH_STACK_SIZE];
  float stack_entry[BVH_STACK_SIZE];
  int sp = 0;
  uint item = 0; /* the root */
  Lanes lanes = BVH8_LANES;
  for (;;) {
    if ((item & WIDE_LEAF_FLAG) == 0) {
      __global const BvhNode8* node = &bvh_nodes[item];
      float8 entry;
      Lanes m = bvh8_test(node, &ray, hit.t, &entry) & lanes;
      lanes = BVH8_LANES;
      if (m == 0) goto pop;
      const Lanes rest = m & (m - 1);
      if (rest == 0) {
        /* The only lane is also the highest: clz is one instruction. */
        item = node->child[bvh8_last_lane(m)];
        continue;
      }
      if ((rest & (rest - 1)) == 0) {
        /* Two children, the commonest case after one: no sort loop. One
         * entry pushed, as a group entry would, so the stack bound holds. */
        const uint a = bvh8_lane(m), b = bvh8_last_lane(m);
        const float ta = entry_lane(entry, a), tb = entry_lane(entry, b);
        const uint ca = node->child[a], cb = node->child[b];
        const bool a_first = ta <= tb;
        const uint far_child = a_first ? cb : ca;
        bvh8_prefetch_item(bvh_nodes, tri_blocks, far_child);
        stack_item[sp] = far_child;
        stack_entry[sp] = a_first ? tb : ta;
        ++sp;
        item = a_first ? ca : cb;
        continue;
      }
      {
        float dist[8];
        vstore8(entry, 0, dist);
        /* On reaching a node, sp + height <= BVH_STACK_SIZE - 1. Leaving
         * k - 1 entries keeps that true for the children exactly when this
         * holds (k - 1 = popcount - 1, children one level lower); a single
         * group entry always keeps it. */
        if (sp + (int)popcount(m) + (int)node->height <= BVH_STACK_SIZE + 1) {
          /* Insertion sort onto the stack, farthest deepest; the nearest
           * ends on top and is taken straight back off. */
          int base = sp;
          for (; m != 0; m &= m - 1) {
            uint lane = bvh8_lane(m);
            float t = dist[lane];
            int j = sp++;
            for (; j > base && stack_entry[j - 1] < t; --j) {
              stack_item[j] = stack_item[j - 1];
              stack_entry[j] = stack_entry[j - 1];
            }
            uint child = node->child[lane];
            bvh8_prefetch_item(bvh_nodes, tri_blocks, child);
            stack_item[j] = child;
            stack_entry[j] = t;
          }
          item = stack_item[--sp];
        } else {
          item = bvh8_push_group(node, item, m, dist, stack_item, stack_entry, &sp);
        }
        continue;
      }
    } else {
      uint first = item & WIDE_LEAF_INDEX_MASK, end = first + wide_leaf_count(item);
#if HAS_SPHERES || HAS_CYLINDERS
      if (item & WIDE_LEAF_PRIMS)
        for (uint i = first; i < end; ++i)
          intersect_prim_ref(spheres, cylinders, triangles, prim_refs[i], o, d, tmin, &hit);
#endif
#if HAS_TRIANGLES
      if (!(item & WIDE_LEAF_PRIMS)) {
        if (!tri_ready) {
          tri = triangle_ray(o, d);
          tri_ready = true;
        }
        for (uint b = first; b < end; ++b)
          triangle_block_closest(&tri_blocks[b], &tri, tmin, &hit, triangle_alpha, alpha_texels, o, d);
      }
#endif
    }
  pop:
    /* Pop, dropping subtrees that start beyond the closest hit so far. */
    do {
      if (sp == 0) return hit;
      --sp;
    } while (stack_entry[sp] > hit.t);
    item = bvh8_unpack(stack_item[sp], &lanes);
  }
}

CS_DEVICE bool trace_any(SCENE_GEOMETRY_PARAMS, float3 o, float3 d, float tmin, float tmax) {
  (void)triangle_alpha; /* read only with HAS_ALPHA_CUTOUTS */
  (void)alpha_texels;
  if (!ray_traceable(o, d)) return false;
  const WideRay ray = wide_ray(o, d, tmin);
#if HAS_TRIANGLES
  /* Set up at the first triangle leaf: rays that reach none skip it. */
  TriangleRay tri;
  bool tri_ready = false;
#endif
  uint stack_item[BVH_STACK_SIZE];
  float stack_entry[BVH_STACK_SIZE]; /* only group entries use it */
  int sp = 0;
  uint item = 0;
  Lanes lanes = BVH8_LANES;
  for (;;) {
    if ((item & WIDE_LEAF_FLAG) == 0) {
      __global const BvhNode8* node = &bvh_nodes[item];
      float8 entry;
      Lanes m = bvh8_test(node, &ray, tmax, &entry) & lanes;
      lanes = BVH8_LANES;
      if (m != 0) {
        /* Any order finds an occluder; no sorting. Highest lane first, the
         * rest pushed lowest first so that they pop from the highest down
         * (see the top of this file). */
        if ((m & (m - 1)) == 0 || sp + (int)popcount(m) + (int)node->height <= BVH_STACK_SIZE + 1) {
          const uint last = bvh8_last_lane(m);
          item = node->child[last];
          for (m = bvh8_without_lane(m, last); m != 0; m &= m - 1) {
            uint child = node->child[bvh8_lane(m)];
            bvh8_prefetch_item(bvh_nodes, tri_blocks, child);
            stack_item[sp++] = child;
          }
        } else {
          float dist[8];
          vstore8(entry, 0, dist);
          item = bvh8_push_group(node, item, m, dist, stack_item, stack_entry, &sp);
        }
        continue;
      }
    } else {
      uint first = item & WIDE_LEAF_INDEX_MASK, end = first + wide_leaf_count(item);
#if HAS_SPHERES || HAS_CYLINDERS
      if (item & WIDE_LEAF_PRIMS) {
        Hit hit = hit_none(tmax);
        for (uint i = first; i < end; ++i)
          if (intersect_prim_ref(spheres, cylinders, triangles, prim_refs[i], o, d, tmin, &hit)) return true;
      }
#endif
#if HAS_TRIANGLES
      if (!(item & WIDE_LEAF_PRIMS)) {
        if (!tri_ready) {
          tri = triangle_ray(o, d);
          tri_ready = true;
        }
        float4 t, u, v;
        for (uint b = first; b < end; ++b) {
          const int4 lanes = intersect_triangle_block(&tri_blocks[b], &tri, tmin, tmax, &t, &u, &v);
#if HAS_ALPHA_CUTOUTS
          if (any4(lanes) &&
              any4(alpha_kept_lanes(&tri_blocks[b], lanes, u, v, triangle_alpha, alpha_texels, o, d)))
            return true;
#else
          if (any4(lanes)) return true;
#endif
        }
      }
#endif
    }
    if (sp == 0) return false;
    item = bvh8_unpack(stack_item[--sp], &lanes);
  }
}

#endif /* CAUSTICA_LIB_BVH_TRAVERSE_H */
