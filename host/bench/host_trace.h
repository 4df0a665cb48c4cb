// The kernels' ray queries on the host: kernels/lib/bvh_traverse.h,
// intersect_primitives.h and the position/normal part of surface.h compiled
// as C++ (kernels/shared/compat.h), over the wide BVH the device traverses,
// collapsed from the given binary one. The benchmark tools use it to
// generate their rays from primary hits and to check both tracers: it is
// the kernels' code, so on PoCL it gives their answers bit for bit. It is
// not meant to be fast (one ray at a time, no SIMD).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "host/scene/scene.h"

namespace caustica {

constexpr float kRayTFar = RAY_T_FAR;

// The kernels' Hit (kernels/shared/types.h) and its "no hit" value.
inline Hit no_hit(float tmax = kRayTFar) { return Hit{tmax, 0.0f, 0.0f, PRIM_NONE}; }
inline bool is_hit(const Hit& hit) { return hit.prim != PRIM_NONE; }

// Primitive tests with the contract of intersect_primitives.h: *t holds tmax
// on input and is lowered only for a hit with tmin < t < *t. Exposed so that
// the Embree reference intersects spheres and cylinders with the same math.
bool host_intersect_sphere(glm::vec3 center, float radius, glm::vec3 o, glm::vec3 d, float tmin, float* t);
bool host_intersect_cylinder(glm::vec3 center, glm::vec3 axis, float radius, float half_length, glm::vec3 o,
                             glm::vec3 d, float tmin, float* t, float* part);
bool host_intersect_triangle(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 o, glm::vec3 d, float tmin,
                             float* t, float* u, float* v);

// What secondary-ray spawning needs from surface_at (kernels/lib/surface.h).
struct HostSurfacePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // geometric, outward
  glm::vec3 p_error{0.0f};  // bound on the position's error per component (surface.h)
};

// spawn_ray_origin of kernels/lib/geometry.h: the origin of a ray leaving the
// surface at p (error bound p_error, geometric normal n) on dir's side.
glm::vec3 host_spawn_ray_origin(glm::vec3 p, glm::vec3 p_error, glm::vec3 n, glm::vec3 dir);
inline glm::vec3 host_spawn_ray_origin(const HostSurfacePoint& sp, glm::vec3 dir) {
  return host_spawn_ray_origin(sp.position, sp.p_error, sp.normal, dir);
}

class HostTracer {
 public:
  // The scene must outlive the tracer; the BVH is collapsed to the wide
  // layout the kernels traverse.
  HostTracer(const Scene& scene, const Bvh& bvh);

  Hit closest(glm::vec3 o, glm::vec3 d, float tmin, float tmax) const;  // trace_closest
  bool any(glm::vec3 o, glm::vec3 d, float tmin, float tmax) const;         // trace_any
  // intersect_prim_ref: tests one encoded primitive, overwriting *hit when nearer.
  bool intersect_prim(uint32_t ref, glm::vec3 o, glm::vec3 d, float tmin, Hit* hit) const;
  HostSurfacePoint surface_at(const Hit& hit, glm::vec3 o, glm::vec3 d) const;

  const Scene& scene() const { return scene_; }

 private:
  const Scene& scene_;
  WideBvh wide_;
};

}  // namespace caustica
