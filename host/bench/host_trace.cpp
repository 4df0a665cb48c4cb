// Every primitive type: the feature flags (kernels/shared/feature_flags.h)
// are set before the first include, which gives the others their defaults.
#define HAS_SPHERES 1
#define HAS_CYLINDERS 1
#define HAS_TRIANGLES 1

#include "host/bench/host_trace.h"

// The kernels' own traversal, primitive tests, ray origins and surface
// points (kernels/lib/, compiled as C++ through kernels/shared/compat.h),
// over the scene's wide BVH. Every primitive type is compiled in (the
// device compiles only the scene's); shading data and textures are not:
// the host surface point is position, geometric normal and error bound.
// Compiled with -ffp-contract=off (CMakeLists.txt), as the kernels evaluate
// intersect_primitives.h with FP_CONTRACT OFF.
#include "lib/bvh_traverse.h"
#include "lib/surface.h"

namespace caustica {
namespace {

float3 f3(glm::vec3 v) { return make_float3(v.x, v.y, v.z); }
glm::vec3 v3(float3 v) { return glm::vec3(v.x, v.y, v.z); }

}  // namespace

bool host_intersect_sphere(glm::vec3 center, float radius, glm::vec3 o, glm::vec3 d, float tmin, float* t) {
  return intersect_sphere(f3(center), radius, f3(o), f3(d), tmin, t);
}

bool host_intersect_cylinder(glm::vec3 center, glm::vec3 axis, float radius, float half_length, glm::vec3 o,
                             glm::vec3 d, float tmin, float* t, float* part) {
  return intersect_cylinder(f3(center), f3(axis), radius, half_length, f3(o), f3(d), tmin, t, part);
}

bool host_intersect_triangle(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 o, glm::vec3 d, float tmin,
                             float* t, float* u, float* v) {
  return intersect_triangle(f3(v0), f3(v1), f3(v2), f3(o), f3(d), tmin, t, u, v);
}

glm::vec3 host_spawn_ray_origin(glm::vec3 p, glm::vec3 p_error, glm::vec3 n, glm::vec3 dir) {
  return v3(spawn_ray_origin(f3(p), f3(p_error), f3(n), f3(dir)));
}

HostTracer::HostTracer(const Scene& scene, const Bvh& bvh) : scene_(scene), wide_(collapse_bvh(bvh, scene)) {}

bool HostTracer::intersect_prim(uint32_t ref, glm::vec3 o, glm::vec3 d, float tmin, Hit* hit) const {
  return intersect_prim_ref(scene_.spheres.data(), scene_.cylinders.data(), scene_.triangles.data(), ref, f3(o), f3(d),
                            tmin, hit);
}

Hit HostTracer::closest(glm::vec3 o, glm::vec3 d, float tmin, float tmax) const {
  // Alpha cut-outs are not compiled here (HAS_ALPHA_CUTOUTS 0): no records.
  return trace_closest(wide_.nodes.data(), wide_.triangle_blocks.data(), wide_.prim_refs.data(), scene_.spheres.data(),
                       scene_.cylinders.data(), scene_.triangles.data(), nullptr, nullptr, f3(o), f3(d), tmin, tmax);
}

bool HostTracer::any(glm::vec3 o, glm::vec3 d, float tmin, float tmax) const {
  return trace_any(wide_.nodes.data(), wide_.triangle_blocks.data(), wide_.prim_refs.data(), scene_.spheres.data(),
                   scene_.cylinders.data(), scene_.triangles.data(), nullptr, nullptr, f3(o), f3(d), tmin, tmax);
}

HostSurfacePoint HostTracer::surface_at(const Hit& hit, glm::vec3 o, glm::vec3 d) const {
  HostSurfacePoint sp;
  sp.position = o + hit.t * d;
  if (!is_hit(hit)) return sp;
  const SurfacePoint s = ::surface_at(scene_.spheres.data(), scene_.cylinders.data(), scene_.triangles.data(),
                                      nullptr, hit, f3(o), f3(d));
  sp.position = v3(s.position);
  sp.normal = v3(s.normal);
  sp.p_error = v3(s.p_error);
  return sp;
}

}  // namespace caustica
