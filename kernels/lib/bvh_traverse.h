#line 2 "kernels/lib/bvh_traverse.h"
/* Closest-hit and any-hit queries over the flattened BVH2 of types.h.
 *
 * Rules: finite arithmetic only (programs may use -cl-fast-relaxed-math):
 * reciprocal directions are clamped to +-BVH_INV_DIR_MAX and empty boxes are
 * stored as lo = +1e18, hi = -1e18, which the slab test rejects because it
 * picks the near/far planes by the ray's direction sign rather than by
 * min/max (min/max would turn an inverted box into the whole space). The
 * builder (host/accel/bvh.cpp) keeps leaves at depth <= BVH_STACK_SIZE, and
 * the traversal pushes at most one node per level. Primitive code is compiled
 * only for the types the scene has (HAS_SPHERES, HAS_CYLINDERS,
 * HAS_TRIANGLES). */
#ifndef CAUSTICA_LIB_BVH_TRAVERSE_H
#define CAUSTICA_LIB_BVH_TRAVERSE_H

#include "lib/geometry.h"
#include "lib/intersect_primitives.h"

#define BVH_STACK_SIZE 64
#define BVH_INV_DIR_MAX 1e18f
/* Widens each box's exit distance (relative) so rounding in the slab test,
 * including the approximate reciprocals fast-relaxed-math may use, never
 * culls a hit on a primitive that touches its box: rays through triangle
 * vertices, which sit exactly on box corners, are the typical victims. */
#define BVH_EXIT_SLACK 2e-6f

/* Tests one primitive (encoded ref) and, on a nearer hit, overwrites *hit. */
bool intersect_prim_ref(__global const Sphere* spheres, __global const Cylinder* cylinders,
                        __global const Triangle* triangles, uint ref, float3 o, float3 d, float tmin, Hit* hit) {
  uint type = prim_ref_type(ref);
  uint index = prim_ref_index(ref);
#ifdef HAS_SPHERES
  if (type == PRIM_SPHERE) {
    float4 s = spheres[index].center_radius;
    if (!intersect_sphere(s.xyz, s.w, o, d, tmin, &hit->t)) return false;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->prim = ref;
    return true;
  }
#endif
#ifdef HAS_CYLINDERS
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
#ifdef HAS_TRIANGLES
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

typedef struct {
  float3 o;
  float3 inv_d; /* clamped reciprocal direction */
  int3 neg;     /* direction sign per axis: selects the near plane */
} BvhRay;

BvhRay bvh_ray(float3 o, float3 d) {
  BvhRay r;
  float3 safe = select(d, copysign((float3)(1.0f / BVH_INV_DIR_MAX), d), fabs(d) < 1.0f / BVH_INV_DIR_MAX);
  r.o = o;
  r.inv_d = clamp(1.0f / safe, -BVH_INV_DIR_MAX, BVH_INV_DIR_MAX);
  r.neg = r.inv_d < 0.0f;
  return r;
}

/* The empty scene's root is the only leaf with count 0 (and offset 0, where
 * an inner node's right child is always > 1). Its inverted box already
 * misses; checking it too keeps an empty scene from ever reading node 1. */
bool bvh_is_empty(__global const BvhNode* bvh_nodes) { return bvh_nodes[0].count == 0 && bvh_nodes[0].offset == 0; }

/* Slab test: true when [entry, exit] meets [tmin, tmax]; *entry receives the
 * entry distance (clamped to tmin) for front-to-back ordering. (plane - o)
 * is formed before scaling so the rounding error stays relative to t even
 * when the box and the origin are both far from the world origin. */
bool bvh_box_hit(__global const BvhNode* node, const BvhRay* r, float tmin, float tmax, float* entry) {
  float3 lo = (float3)(node->lo_x, node->lo_y, node->lo_z);
  float3 hi = (float3)(node->hi_x, node->hi_y, node->hi_z);
  float3 t0 = (select(lo, hi, r->neg) - r->o) * r->inv_d;
  float3 t1 = (select(hi, lo, r->neg) - r->o) * r->inv_d;
  float t_enter = fmax(fmax(t0.x, t0.y), fmax(t0.z, tmin));
  float t_exit = fmin(fmin(t1.x, t1.y), t1.z);
  t_exit += fabs(t_exit) * BVH_EXIT_SLACK;
  *entry = t_enter;
  return t_enter <= fmin(t_exit, tmax);
}

Hit trace_closest(SCENE_GEOMETRY_PARAMS, float3 o, float3 d, float tmin, float tmax) {
  Hit hit = hit_none(tmax);
  BvhRay ray = bvh_ray(o, d);
  uint stack_node[BVH_STACK_SIZE];
  float stack_entry[BVH_STACK_SIZE];
  int sp = 0;
  float entry;
  if (bvh_is_empty(bvh_nodes) || !bvh_box_hit(&bvh_nodes[0], &ray, tmin, tmax, &entry)) return hit;
  uint node = 0;
  for (;;) {
    __global const BvhNode* n = &bvh_nodes[node];
    if (n->count > 0) {
      for (uint i = n->offset; i < n->offset + n->count; ++i)
        intersect_prim_ref(spheres, cylinders, triangles, prim_refs[i], o, d, tmin, &hit);
    } else {
      uint near_child = node + 1, far_child = n->offset;
      float t_near, t_far;
      bool hit_near = bvh_box_hit(&bvh_nodes[near_child], &ray, tmin, hit.t, &t_near);
      bool hit_far = bvh_box_hit(&bvh_nodes[far_child], &ray, tmin, hit.t, &t_far);
      if (hit_near && hit_far) {
        if (t_far < t_near) {
          uint tn = near_child;
          near_child = far_child;
          far_child = tn;
          float tt = t_near;
          t_near = t_far;
          t_far = tt;
        }
        stack_node[sp] = far_child;
        stack_entry[sp] = t_far;
        ++sp;
        node = near_child;
        continue;
      }
      if (hit_near || hit_far) {
        node = hit_near ? near_child : far_child;
        continue;
      }
    }
    /* Pop, dropping subtrees that start beyond the closest hit so far. */
    bool found = false;
    while (sp > 0) {
      --sp;
      if (stack_entry[sp] <= hit.t) {
        node = stack_node[sp];
        found = true;
        break;
      }
    }
    if (!found) break;
  }
  return hit;
}

bool trace_any(SCENE_GEOMETRY_PARAMS, float3 o, float3 d, float tmin, float tmax) {
  BvhRay ray = bvh_ray(o, d);
  uint stack_node[BVH_STACK_SIZE];
  int sp = 0;
  float entry;
  if (bvh_is_empty(bvh_nodes) || !bvh_box_hit(&bvh_nodes[0], &ray, tmin, tmax, &entry)) return false;
  Hit hit = hit_none(tmax);
  uint node = 0;
  for (;;) {
    __global const BvhNode* n = &bvh_nodes[node];
    if (n->count > 0) {
      for (uint i = n->offset; i < n->offset + n->count; ++i)
        if (intersect_prim_ref(spheres, cylinders, triangles, prim_refs[i], o, d, tmin, &hit)) return true;
    } else {
      uint left = node + 1, right = n->offset;
      bool hit_left = bvh_box_hit(&bvh_nodes[left], &ray, tmin, tmax, &entry);
      bool hit_right = bvh_box_hit(&bvh_nodes[right], &ray, tmin, tmax, &entry);
      if (hit_left && hit_right) stack_node[sp++] = right;
      if (hit_left || hit_right) {
        node = hit_left ? left : right;
        continue;
      }
    }
    if (sp == 0) break;
    node = stack_node[--sp];
  }
  return false;
}

#endif /* CAUSTICA_LIB_BVH_TRAVERSE_H */
