#include "host/bench/host_trace.h"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <utility>

// Compiled with -ffp-contract=off (CMakeLists.txt): the kernels evaluate
// intersect_primitives.h with FP_CONTRACT OFF, and a fused multiply-add here
// would move edge functions and roots by an ulp.

namespace caustica {
namespace {

using glm::vec3;

constexpr float kCylPartSide = CYL_PART_SIDE;
constexpr float kCylPartTop = CYL_PART_TOP;
constexpr float kCylPartBottom = CYL_PART_BOTTOM;
constexpr int kStackSize = CS_BVH_STACK_SIZE;
constexpr float kInvDirMax = BVH_INV_DIR_MAX;
constexpr float kExitSlack = BVH_EXIT_SLACK;

// OpenCL's dot is written out so that the summation order is the kernels'.
float dot3(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
vec3 normalize3(vec3 v) { return v / std::sqrt(dot3(v, v)); }

bool accept_root(float t, float tmin, float* tbest) {
  if (t > tmin && t < *tbest) {
    *tbest = t;
    return true;
  }
  return false;
}

bool solve_quadratic(float a, float b, float c, float disc, float* s0, float* s1) {
  if (disc < 0.0f) return false;
  const float q = -(b + std::copysign(std::sqrt(disc), b));
  const float r0 = q / a;
  const float r1 = q != 0.0f ? c / q : r0;
  *s0 = std::fmin(r0, r1);
  *s1 = std::fmax(r0, r1);
  return true;
}

float component(vec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

vec3 shear_vertex(vec3 v, vec3 o, int kx, int ky, int kz, vec3 shear) {
  const vec3 a = v - o;
  const float az = component(a, kz);
  return vec3(component(a, kx) - shear.x * az, component(a, ky) - shear.y * az, shear.z * az);
}

// The kernels enable cl_khr_fp64 whenever the device has it (PoCL does), so
// the exact double fallback for near-zero edge functions is always on here.
float edge_function(float px, float py, float qx, float qy) {
  float e = px * qy - py * qx;
  const float bound = 2.5e-7f * (std::fabs(px * qy) + std::fabs(py * qx));
  if (std::fabs(e) <= bound) e = float(double(px) * double(qy) - double(py) * double(qx));
  return e;
}

float max_abs3(vec3 v) { return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z))); }

float error_gamma(float n) { return (n * 0x1.0p-24f) / (1.0f - n * 0x1.0p-24f); }

float float_step(float x, bool up) {
  if (x == 0.0f) return up ? FLT_MIN : -FLT_MIN;
  int32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits += ((x > 0.0f) == up) ? 1 : -1;
  float out;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

struct BoxRay {
  vec3 o, inv_d;
  bool neg[3];
};

BoxRay box_ray(vec3 o, vec3 d) {
  BoxRay r;
  r.o = o;
  for (int k = 0; k < 3; ++k) {
    float dk = d[k];
    if (std::fabs(dk) < 1.0f / kInvDirMax) dk = std::copysign(1.0f / kInvDirMax, dk);
    r.inv_d[k] = std::fmin(std::fmax(1.0f / dk, -kInvDirMax), kInvDirMax);
    r.neg[k] = r.inv_d[k] < 0.0f;
  }
  return r;
}

bool box_hit(const BvhNode& n, const BoxRay& r, float tmin, float tmax, float* entry) {
  const float lo[3] = {n.lo_x, n.lo_y, n.lo_z};
  const float hi[3] = {n.hi_x, n.hi_y, n.hi_z};
  float t0[3], t1[3];
  for (int k = 0; k < 3; ++k) {
    t0[k] = ((r.neg[k] ? hi[k] : lo[k]) - r.o[k]) * r.inv_d[k];
    t1[k] = ((r.neg[k] ? lo[k] : hi[k]) - r.o[k]) * r.inv_d[k];
  }
  const float t_enter = std::fmax(std::fmax(t0[0], t0[1]), std::fmax(t0[2], tmin));
  float t_exit = std::fmin(std::fmin(t1[0], t1[1]), t1[2]);
  t_exit += std::fabs(t_exit) * kExitSlack;
  *entry = t_enter;
  return t_enter <= std::fmin(t_exit, tmax);
}

bool bvh_empty(const Bvh& bvh) { return bvh.nodes[0].count == 0 && bvh.nodes[0].offset == 0; }

// ray_traceable of kernels/lib/bvh_traverse.h: rays outside the traversal's
// domain miss there, so they miss here too (this binary BVH has no empty
// slots to crash on, but the answers must agree).
bool ray_traceable(vec3 o, vec3 d) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(o[k]) || !std::isfinite(d[k])) return false;
  const float d_max = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
  const float o_max = std::fmax(std::fabs(o.x), std::fmax(std::fabs(o.y), std::fabs(o.z)));
  return d_max >= 1.0f / kInvDirMax && d_max <= kInvDirMax && o_max <= BVH_ORIGIN_MAX;
}

}  // namespace

bool host_intersect_sphere(vec3 center, float radius, vec3 o, vec3 d, float tmin, float* t) {
  const vec3 f = o - center;
  const float a = dot3(d, d);
  const float b = dot3(f, d);
  const vec3 perp = f - (b / a) * d;
  const float disc = a * (radius * radius - dot3(perp, perp));
  const float c = dot3(f, f) - radius * radius;
  float t0, t1;
  if (!solve_quadratic(a, b, c, disc, &t0, &t1)) return false;
  return accept_root(t0, tmin, t) || accept_root(t1, tmin, t);
}

bool host_intersect_cylinder(vec3 center, vec3 axis, float radius, float half_length, vec3 o, vec3 d, float tmin,
                             float* t, float* part) {
  const vec3 f = o - center;
  const float fz = dot3(f, axis);
  const float dz = dot3(d, axis);
  const vec3 fp = f - fz * axis;
  const vec3 dp = d - dz * axis;
  const float a = dot3(dp, dp);
  const float dd = dot3(d, d);
  bool hit = false;
  // As the kernel: an origin outside the side moving away never meets it.
  const bool leaving_side = dot3(fp, fp) > radius * radius && dot3(fp, dp) >= 0.0f;
  if (!leaving_side && a > 1e-12f * dd) {
    const float tc = -dot3(fp, dp) / a;
    const vec3 g = fp + tc * dp;
    const float zc = fz + tc * dz;
    const float b = dot3(g, dp);
    const float c = dot3(g, g) - radius * radius;
    const vec3 perp = g - (b / a) * dp;
    const float disc = a * (radius * radius - dot3(perp, perp));
    float s0, s1;
    if (solve_quadratic(a, b, c, disc, &s0, &s1)) {
      if (std::fabs(zc + s0 * dz) <= half_length && accept_root(tc + s0, tmin, t)) {
        *part = kCylPartSide;
        hit = true;
      } else if (std::fabs(zc + s1 * dz) <= half_length && accept_root(tc + s1, tmin, t)) {
        *part = kCylPartSide;
        hit = true;
      }
    }
  }
  if (dz * dz > 1e-24f * dd) {
    const float r2 = radius * radius;
    const float t_top = (half_length - fz) / dz;
    const vec3 p_top = fp + t_top * dp;
    if (dot3(p_top, p_top) <= r2 && accept_root(t_top, tmin, t)) {
      *part = kCylPartTop;
      hit = true;
    }
    const float t_bottom = (-half_length - fz) / dz;
    const vec3 p_bottom = fp + t_bottom * dp;
    if (dot3(p_bottom, p_bottom) <= r2 && accept_root(t_bottom, tmin, t)) {
      *part = kCylPartBottom;
      hit = true;
    }
  }
  return hit;
}

bool host_intersect_triangle(vec3 v0, vec3 v1, vec3 v2, vec3 o, vec3 d, float tmin, float* t, float* u, float* v) {
  const vec3 ad = glm::abs(d);
  const int kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  const float dkz = component(d, kz);
  if (dkz < 0.0f) std::swap(kx, ky);
  const vec3 shear(component(d, kx) / dkz, component(d, ky) / dkz, 1.0f / dkz);
  const vec3 a = shear_vertex(v0, o, kx, ky, kz, shear);
  const vec3 b = shear_vertex(v1, o, kx, ky, kz, shear);
  const vec3 c = shear_vertex(v2, o, kx, ky, kz, shear);
  const float e0 = edge_function(c.x, c.y, b.x, b.y);
  const float e1 = edge_function(a.x, a.y, c.x, c.y);
  const float e2 = edge_function(b.x, b.y, a.x, a.y);
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return false;
  const float det = e0 + e1 + e2;
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const float th = (e0 * a.z + e1 * b.z + e2 * c.z) * inv;
  if (!accept_root(th, tmin, t)) return false;
  *u = e1 * inv;
  *v = e2 * inv;
  return true;
}

vec3 host_spawn_ray_origin(vec3 p, vec3 p_error, vec3 n, vec3 dir) {
  const float d = dot3(glm::abs(n), p_error);
  vec3 offset = d * n;
  if (dot3(dir, n) < 0.0f) offset = -offset;
  vec3 po = p + offset;
  for (int k = 0; k < 3; ++k)
    if (offset[k] != 0.0f) po[k] = float_step(po[k], offset[k] > 0.0f);
  return po;
}

bool HostTracer::intersect_prim(uint32_t ref, vec3 o, vec3 d, float tmin, Hit* hit) const {
  const uint32_t type = ref >> PRIM_TYPE_SHIFT;
  const uint32_t index = ref & PRIM_INDEX_MASK;
  if (type == PRIM_SPHERE) {
    const cs_float4 s = scene_.spheres[index].center_radius;
    if (!host_intersect_sphere(to_vec3(s), s.w, o, d, tmin, &hit->t)) return false;
    hit->u = hit->v = 0.0f;
  } else if (type == PRIM_CYLINDER) {
    const Cylinder& cyl = scene_.cylinders[index];
    const vec3 center = to_vec3(cyl.center_radius), axis = to_vec3(cyl.axis_half);
    float t = hit->t, part = 0.0f;
    if (!host_intersect_cylinder(center, axis, cyl.center_radius.w, cyl.axis_half.w, o, d, tmin, &t, &part))
      return false;
    hit->t = t;
    hit->u = part;
    hit->v = dot3(o - center, axis) + t * dot3(d, axis);
  } else if (type == PRIM_TRIANGLE) {
    const Triangle& tri = scene_.triangles[index];
    float t = hit->t, u = 0.0f, v = 0.0f;
    if (!host_intersect_triangle(to_vec3(tri.v0), to_vec3(tri.v1), to_vec3(tri.v2), o, d, tmin, &t, &u, &v))
      return false;
    hit->t = t;
    hit->u = u;
    hit->v = v;
  } else {
    return false;
  }
  hit->prim = ref;
  return true;
}

Hit HostTracer::closest(vec3 o, vec3 d, float tmin, float tmax) const {
  Hit hit = no_hit(tmax);
  const BoxRay ray = box_ray(o, d);
  uint32_t stack_node[kStackSize];
  float stack_entry[kStackSize];
  int sp = 0;
  float entry;
  const BvhNode* nodes = bvh_.nodes.data();
  if (!ray_traceable(o, d) || bvh_empty(bvh_) || !box_hit(nodes[0], ray, tmin, tmax, &entry)) return hit;
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = nodes[node];
    if (n.count > 0) {
      for (uint32_t i = n.offset; i < n.offset + n.count; ++i) intersect_prim(bvh_.prim_refs[i], o, d, tmin, &hit);
    } else {
      uint32_t near_child = node + 1, far_child = n.offset;
      float t_near, t_far;
      const bool hit_near = box_hit(nodes[near_child], ray, tmin, hit.t, &t_near);
      const bool hit_far = box_hit(nodes[far_child], ray, tmin, hit.t, &t_far);
      if (hit_near && hit_far) {
        if (t_far < t_near) {
          std::swap(near_child, far_child);
          std::swap(t_near, t_far);
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

bool HostTracer::any(vec3 o, vec3 d, float tmin, float tmax) const {
  const BoxRay ray = box_ray(o, d);
  uint32_t stack_node[kStackSize];
  int sp = 0;
  float entry;
  const BvhNode* nodes = bvh_.nodes.data();
  if (!ray_traceable(o, d) || bvh_empty(bvh_) || !box_hit(nodes[0], ray, tmin, tmax, &entry)) return false;
  Hit hit = no_hit(tmax);
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = nodes[node];
    if (n.count > 0) {
      for (uint32_t i = n.offset; i < n.offset + n.count; ++i)
        if (intersect_prim(bvh_.prim_refs[i], o, d, tmin, &hit)) return true;
    } else {
      const uint32_t left = node + 1, right = n.offset;
      const bool hit_left = box_hit(nodes[left], ray, tmin, tmax, &entry);
      const bool hit_right = box_hit(nodes[right], ray, tmin, tmax, &entry);
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

HostSurfacePoint HostTracer::surface_at(const Hit& hit, vec3 o, vec3 d) const {
  HostSurfacePoint sp;
  sp.position = o + hit.t * d;
  const uint32_t type = hit.prim >> PRIM_TYPE_SHIFT;
  const uint32_t index = hit.prim & PRIM_INDEX_MASK;
  if (!is_hit(hit)) return sp;
  if (type == PRIM_SPHERE) {
    const cs_float4 s = scene_.spheres[index].center_radius;
    const vec3 c = to_vec3(s);
    sp.normal = normalize3((o - c) + hit.t * d);
    sp.position = c + s.w * sp.normal;
    sp.p_error = error_gamma(8.0f) * glm::abs(s.w * sp.normal) + error_gamma(1.0f) * glm::abs(sp.position);
  } else if (type == PRIM_CYLINDER) {
    const Cylinder& cyl = scene_.cylinders[index];
    const vec3 c = to_vec3(cyl.center_radius), axis = to_vec3(cyl.axis_half);
    const float radius = cyl.center_radius.w, half_length = cyl.axis_half.w;
    const vec3 rel = (o - c) + hit.t * d;
    const float z = std::fmin(std::fmax(dot3(rel, axis), -half_length), half_length);
    vec3 radial = rel - dot3(rel, axis) * axis;
    const float len = std::sqrt(dot3(radial, radial));
    if (hit.u == kCylPartSide) {
      sp.normal = len > 0.0f ? radial / len : normalize3(glm::cross(axis, vec3(axis.y, axis.z, axis.x)));
      sp.position = c + z * axis + radius * sp.normal;
    } else {
      const float sgn = hit.u == kCylPartTop ? 1.0f : -1.0f;
      sp.normal = sgn * axis;
      if (len > radius) radial *= radius / len;
      sp.position = c + (sgn * half_length) * axis + radial;
    }
    sp.p_error = error_gamma(2.0f) * glm::abs(sp.position) + error_gamma(8.0f) * vec3(radius + half_length);
  } else if (type == PRIM_TRIANGLE) {
    const Triangle& tri = scene_.triangles[index];
    const vec3 v0 = to_vec3(tri.v0), v1 = to_vec3(tri.v1), v2 = to_vec3(tri.v2);
    sp.position = v0 + hit.u * (v1 - v0) + hit.v * (v2 - v0);
    sp.normal = normalize3(glm::cross(v1 - v0, v2 - v0));
    const vec3 e1 = v1 - v0, e2 = v2 - v0;
    sp.p_error = error_gamma(7.0f) * (glm::abs(v0) + glm::abs(hit.u * e1) + glm::abs(hit.v * e2)) +
                 vec3(error_gamma(32.0f) * (max_abs3(e1) + max_abs3(e2)));
  }
  return sp;
}

}  // namespace caustica
