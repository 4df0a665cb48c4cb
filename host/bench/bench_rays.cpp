#include "host/bench/bench_rays.h"

#include <algorithm>
#include <cmath>

#include "host/error.h"
#include "host/math_constants.h"
#include "host/parallel.h"
#include "host/lights/light_types.h"
#include "kernels/shared/camera.h"

namespace caustica {
namespace {

using glm::vec3;

// SplitMix64's finaliser: a full-avalanche hash, so consecutive ray indices
// give independent-looking numbers without any sequential state.
uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

float dot3(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace

RaySet camera_rays(const CameraDesc& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw Error("bench rays: image size must be positive");
  // The renderer's camera: the same CameraGPU and the same plane point
  // (kernels/shared/camera.h) as generate_camera_rays.
  const CameraGPU cam = camera_for_image(camera, width, height);
  RaySet rays;
  const size_t pixels = size_t(width) * size_t(height);
  rays.origin.assign(pixels, to_float4(camera.position));
  rays.dir.resize(pixels);
  for (size_t pixel = 0; pixel < pixels; ++pixel) {
    float p[3];
    camera_pixel_centre_point(&cam, cs_uint(pixel), p);
    const vec3 v(p[0], p[1], p[2]);
    rays.dir[pixel] = to_float4(v / std::sqrt(dot3(v, v)));
  }
  return rays;
}

vec3 cosine_direction(vec3 n, uint64_t seed, uint64_t index) {
  const uint64_t h = mix64(seed ^ mix64(index));
  // Two 24-bit uniforms in [0, 1): u1 < 1 keeps z = sqrt(1 - u1) >= 2^-12,
  // so no direction is tangent to the surface.
  const double u1 = double(h >> 40) * 0x1.0p-24;
  const double u2 = double((h >> 16) & 0xFFFFFF) * 0x1.0p-24;
  // Malley: uniform on the disc, projected up onto the hemisphere.
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  const double x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(1.0 - u1);
  // Orthonormal basis around n without a branch on the axis (Duff et al. 2017).
  const glm::dvec3 nd(n);
  const double sign = std::copysign(1.0, nd.z);
  const double a = -1.0 / (sign + nd.z), b = nd.x * nd.y * a;
  const glm::dvec3 t1(1.0 + sign * nd.x * nd.x * a, sign * b, -sign * nd.x);
  const glm::dvec3 t2(b, sign + nd.y * nd.y * a, -nd.y);
  return vec3(glm::normalize(x * t1 + y * t2 + z * nd));
}

std::vector<Hit> host_closest_hits(const HostTracer& tracer, const RaySet& rays, int threads) {
  std::vector<Hit> hits(rays.size());
  parallel_blocks(rays.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) hits[i] = tracer.closest(rays.o(i), rays.d(i), 0.0f, rays.tmax(i));
  });
  return hits;
}

std::vector<uint8_t> host_occlusion(const HostTracer& tracer, const RaySet& rays, int threads) {
  std::vector<uint8_t> occluded(rays.size());
  parallel_blocks(rays.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) occluded[i] = tracer.any(rays.o(i), rays.d(i), 0.0f, rays.tmax(i)) ? 1 : 0;
  });
  return occluded;
}

BenchRays generate_bench_rays(const Scene& scene, const Bvh& bvh, int width, int height,
                              const BenchRayOptions& options) {
  BenchRays out;
  out.width = width;
  out.height = height;
  out.primary = camera_rays(scene.camera, width, height);
  const HostTracer tracer(scene, bvh);
  out.primary_hits = host_closest_hits(tracer, out.primary, options.threads);
  for (const Light& l : scene.lights)  // the first point light
    if (l.kind == LIGHT_POINT && !out.has_light) {
      out.has_light = true;
      out.light = to_vec3(l.p0);
    }
  out.shadow.segments = true;

  // Sequential and in pixel order, so the compacted sets do not depend on
  // the thread count.
  for (size_t i = 0; i < out.primary.size(); ++i) {
    const Hit& hit = out.primary_hits[i];
    if (!is_hit(hit)) continue;
    const vec3 o = out.primary.o(i), d = out.primary.d(i);
    const HostSurfacePoint sp = tracer.surface_at(hit, o, d);

    // As shade_surface_phong.cl: the geometric normal turned toward the ray.
    const vec3 facing = dot3(sp.normal, d) < 0.0f ? sp.normal : -sp.normal;
    out.diffuse.origin.push_back(to_float4(host_spawn_ray_origin(sp, facing)));
    out.diffuse.dir.push_back(to_float4(cosine_direction(facing, options.seed, i)));
    out.diffuse_source.push_back(uint32_t(i));

    if (!out.has_light) continue;
    // Leaves on the side of the surface the light is on: a segment that
    // started by crossing its own surface would test nothing but that surface.
    // (The renderer skips those lights instead; the bench keeps one shadow
    // ray per hit so that every scene has a full set.)
    const vec3 toward = dot3(sp.normal, out.light - sp.position) >= 0.0f ? sp.normal : -sp.normal;
    const vec3 origin = host_spawn_ray_origin(sp, toward);
    const vec3 to_light = out.light - origin;
    const float dist = std::sqrt(dot3(to_light, to_light));
    if (!(dist > 0.0f)) continue;
    out.shadow.origin.push_back(to_float4(origin, dist * (1.0f - kShadowEndFraction)));
    out.shadow.dir.push_back(to_float4(to_light / dist));
    out.shadow_source.push_back(uint32_t(i));
  }
  return out;
}

}  // namespace caustica
