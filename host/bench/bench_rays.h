// The ray sets of the traversal benchmarks, generated once on the host so
// that `caustica bench` (OpenCL kernels) and `caustica_embree_bench` (Embree)
// trace exactly the same rays:
//   primary: one ray per pixel through its centre, by the renderer's own
//            camera function (kernels/shared/camera.h);
//   diffuse: one per primary hit, cosine-distributed about the geometric
//            normal on the side the primary ray came from;
//   shadow:  one per primary hit, a segment toward the scene's first point
//            light that ends just short of it.
// Secondary origins use the renderer's spawn rule (host_spawn_ray_origin). Primary
// hits come from HostTracer, not from either tracer under test, and the
// diffuse directions from a counter-based RNG (a hash of the ray index), so
// the sets depend on nothing but the scene, the image size and the seed:
// not on threads, devices or timing.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "host/bench/host_trace.h"

namespace caustica {

// Rays in the kernels' queue layout, ready to upload: origin.xyz / dir.xyz,
// dir unit length. For segments (shadow rays) origin.w is tmax (the bench's
// own packing: the renderer's shadow queue has a tmax field); otherwise
// origin.w is 0 and tmax is kRayTFar.
struct RaySet {
  std::vector<cs_float4> origin;
  std::vector<cs_float4> dir;
  bool segments = false;

  size_t size() const { return origin.size(); }
  glm::vec3 o(size_t i) const { return to_vec3(origin[i]); }
  glm::vec3 d(size_t i) const { return to_vec3(dir[i]); }
  float tmax(size_t i) const { return segments ? origin[i].w : kRayTFar; }
};

struct BenchRays {
  int width = 0, height = 0;
  RaySet primary, diffuse, shadow;
  std::vector<Hit> primary_hits;      // HostTracer's closest hit of every primary ray
  std::vector<uint32_t> diffuse_source;   // primary ray each diffuse ray comes from
  std::vector<uint32_t> shadow_source;    // primary ray each shadow ray comes from
  bool has_light = false;                 // false: the scene has no point light, no shadow rays
  glm::vec3 light{0.0f};                  // position of the scene's first point light
};

struct BenchRayOptions {
  uint64_t seed = 0x5EEDC0FFEEull;
  int threads = 0;  // host threads for the primary trace; 0: all hardware threads
};

// Shadow segments end this fraction short of the light, as in shade_surface_phong.cl.
constexpr float kShadowEndFraction = 1e-5f;

// Throws caustica::Error for a non-positive image size.
BenchRays generate_bench_rays(const Scene& scene, const Bvh& bvh, int width, int height,
                              const BenchRayOptions& options = {});

RaySet camera_rays(const CameraDesc& camera, int width, int height);

// A unit direction, cosine-distributed about the unit normal n, for ray
// `index`: the same (n, seed, index) gives the same bits on every run.
glm::vec3 cosine_direction(glm::vec3 n, uint64_t seed, uint64_t index);

// Host reference answers for a set: closest hits (any set) and occlusion
// (over [0, tmax(i)], meant for segments).
std::vector<Hit> host_closest_hits(const HostTracer& tracer, const RaySet& rays, int threads = 0);
std::vector<uint8_t> host_occlusion(const HostTracer& tracer, const RaySet& rays, int threads = 0);


}  // namespace caustica
