// The benchmark ray sets (host/bench/bench_rays.h) and the host trace they
// come from (host/bench/host_trace.h). `caustica bench` and the Embree
// reference only compare like with like if (a) both get bit-identical rays,
// (b) the host trace that picks the primary hits answers as the OpenCL
// kernels do, and (c) the rays are the kinds they claim to be: diffuse rays
// cosine-distributed on the incoming side, shadow rays aimed at the light
// and stopping short of it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

#include "host/bench/bench_rays.h"
#include "host/bench/ray_batch.h"
#include "host/render/device_scene.h"
#include "host/render/kernel_args.h"
#include "host/scene/features.h"
#include "host/scene/generate.h"
#include "host/scene/load_scene.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using glm::vec3;

constexpr int kWidth = 200, kHeight = 150;

// Spheres, cylinders and triangles above a ground sphere, two point lights.
struct Fixture {
  Scene scene;
  Bvh bvh;
  BenchRays rays;
  Fixture() {
    scene = parse_scene(generate_table1_scene(400, true, 7), "mixed.json", ".");
    bvh = build_bvh(scene);
    rays = generate_bench_rays(scene, bvh, kWidth, kHeight);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

bool same_bits(const RaySet& a, const RaySet& b) {
  return a.size() == b.size() && a.segments == b.segments &&
         std::memcmp(a.origin.data(), b.origin.data(), a.size() * sizeof(cs_float4)) == 0 &&
         std::memcmp(a.dir.data(), b.dir.data(), a.size() * sizeof(cs_float4)) == 0;
}

float dot3(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

TEST(BenchRays, SceneIsMixedAndMostlyHit) {
  const Fixture& f = fixture();
  ASSERT_FALSE(f.scene.spheres.empty());
  ASSERT_FALSE(f.scene.cylinders.empty());
  ASSERT_FALSE(f.scene.triangles.empty());
  ASSERT_TRUE(f.rays.has_light);
  EXPECT_EQ(f.rays.primary.size(), size_t(kWidth) * kHeight);
  EXPECT_GT(f.rays.diffuse.size(), f.rays.primary.size() / 3);
}

TEST(BenchRays, DeterministicAcrossRunsAndThreadCounts) {
  const Fixture& f = fixture();
  BenchRayOptions one_thread;
  one_thread.threads = 1;
  BenchRayOptions three_threads;
  three_threads.threads = 3;
  for (const BenchRayOptions& options : {one_thread, three_threads}) {
    const BenchRays again = generate_bench_rays(f.scene, f.bvh, kWidth, kHeight, options);
    EXPECT_TRUE(same_bits(again.primary, f.rays.primary));
    EXPECT_TRUE(same_bits(again.diffuse, f.rays.diffuse));
    EXPECT_TRUE(same_bits(again.shadow, f.rays.shadow));
    EXPECT_EQ(again.diffuse_source, f.rays.diffuse_source);
    EXPECT_EQ(again.shadow_source, f.rays.shadow_source);
  }
  BenchRayOptions other_seed;
  other_seed.seed = 12345;
  const BenchRays reseeded = generate_bench_rays(f.scene, f.bvh, kWidth, kHeight, other_seed);
  EXPECT_TRUE(same_bits(reseeded.primary, f.rays.primary));
  EXPECT_FALSE(same_bits(reseeded.diffuse, f.rays.diffuse));
}

TEST(BenchRays, OneSecondaryRayPerPrimaryHitOnly) {
  const Fixture& f = fixture();
  size_t hits = 0;
  for (const Hit& h : f.rays.primary_hits) hits += is_hit(h);
  EXPECT_EQ(f.rays.diffuse.size(), hits);
  EXPECT_EQ(f.rays.shadow.size(), hits);
  for (uint32_t source : f.rays.diffuse_source) ASSERT_TRUE(is_hit(f.rays.primary_hits[source]));
  for (uint32_t source : f.rays.shadow_source) ASSERT_TRUE(is_hit(f.rays.primary_hits[source]));
}

// Primary rays against generate_camera_rays.cl: both call the one camera
// function (kernels/shared/camera.h) on the same CameraGPU; only the final
// normalisation differs (OpenCL's normalize against v / |v|).
TEST(BenchRays, PrimaryRaysAreTheRenderersCameraRays) {
  const Fixture& f = fixture();
  Runtime& rt = test::runtime();
  const BuiltProgram render =
      rt.build_file("integrator_phong.cl", analyse_scene(f.scene, RenderMode::Phong).build_options());
  const CameraGPU cam = camera_for_image(f.scene.camera, kWidth, kHeight);
  const size_t n = f.rays.primary.size();
  const DeviceQueue rays(rt.context(), path_record_layout(), n);
  StageKernel generate(render.program, "generate_camera_rays");
  cl::Buffer next_count(rt.context(), CL_MEM_READ_WRITE, sizeof(cl_uint));
  KernelArgs(generate).arg("camera", cam).queue("out", rays).arg("next_count", next_count).finish();
  rt.queue().enqueueNDRangeKernel(generate.kernel, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
  std::vector<cs_float4> o(n), d(n);
  rt.queue().enqueueReadBuffer(rays.field("origin"), CL_TRUE, 0, n * sizeof(cs_float4), o.data());
  rt.queue().enqueueReadBuffer(rays.field("dir"), CL_TRUE, 0, n * sizeof(cs_float4), d.data());
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(to_vec3(o[i]), f.rays.primary.o(i)) << "pixel " << i;
    const vec3 delta = to_vec3(d[i]) - f.rays.primary.d(i);
    ASSERT_LT(std::sqrt(dot3(delta, delta)), 1e-6f) << "pixel " << i;
  }
}

// The traversal port against a brute-force loop over every primitive with
// the same primitive tests: any difference is a traversal bug, not rounding.
TEST(HostTrace, ClosestEqualsBruteForce) {
  const Fixture& f = fixture();
  const HostTracer tracer(f.scene, f.bvh);
  const RaySet* sets[] = {&f.rays.primary, &f.rays.diffuse};
  for (const RaySet* set : sets) {
    for (size_t i = 0; i < set->size(); i += 7) {
      Hit brute = no_hit();
      for (uint32_t ref : f.bvh.prim_refs) tracer.intersect_prim(ref, set->o(i), set->d(i), 0.0f, &brute);
      const Hit h = tracer.closest(set->o(i), set->d(i), 0.0f, set->tmax(i));
      ASSERT_EQ(h.prim, brute.prim) << "ray " << i;
      ASSERT_EQ(h.t, brute.t) << "ray " << i;
      ASSERT_EQ(tracer.any(set->o(i), set->d(i), 0.0f, set->tmax(i)), is_hit(brute)) << "ray " << i;
    }
  }
}

// The kernels and the host trace on the same rays: same primitive, t, u, v
// equal to rounding. A handful of rounding ties (a ray through a shared edge) may
// pick the other triangle; more than 1 in 10^4 is a port bug.
TEST(HostTrace, MatchesOpenClKernels) {
  const Fixture& f = fixture();
  Runtime& rt = test::runtime();
  const SceneFeatures features = analyse_scene(f.scene, RenderMode::Phong);
  const BuiltProgram render = rt.build_file("integrator_phong.cl", features.build_options());
  const BuiltProgram bench = rt.build_file("bench/trace_shadow_only.cl", features.build_options());
  const WideBvh wide = collapse_bvh(f.bvh, f.scene);
  const DeviceScene device_scene(rt.context(), f.scene, wide, features);
  StageKernel closest(render.program, "intersect_closest");
  StageKernel any(bench.program, "trace_shadow_only");
  const HostTracer tracer(f.scene, f.bvh);
  // Every 64th ray of each set on Oclgrind: a spread over the whole image.
  const size_t stride = test::sized(1, 64);
  auto every = [&](const RaySet& s) {
    RaySet c;
    c.segments = s.segments;
    for (size_t i = 0; i < s.size(); i += stride) {
      c.origin.push_back(s.origin[i]);
      c.dir.push_back(s.dir[i]);
    }
    return c;
  };
  const RaySet primary = every(f.rays.primary), diffuse = every(f.rays.diffuse), shadow = every(f.rays.shadow);
  std::vector<Hit> primary_hits;
  for (size_t i = 0; i < f.rays.primary_hits.size(); i += stride) primary_hits.push_back(f.rays.primary_hits[i]);

  const RaySet* sets[] = {&primary, &diffuse};
  for (const RaySet* set : sets) {
    std::vector<Hit> hits(set->size());
    time_ray_kernel(rt, device_scene, closest, "hits", set->origin, set->dir, sizeof(Hit), 1, hits.data());
    const std::vector<Hit> ref = set == &primary ? primary_hits : host_closest_hits(tracer, *set);
    size_t differ = 0, off = 0;
    std::ostringstream first_off;
    for (size_t i = 0; i < set->size(); ++i) {
      const uint32_t prim = hits[i].prim;
      if (prim != ref[i].prim) {
        ++differ;
        continue;
      }
      if (prim == PRIM_NONE) continue;
      // t, then u and v (barycentrics; cylinder part and axial coordinate),
      // which the ray generator turns into secondary origins. Bit-equal on
      // PoCL; a device that rounds otherwise (NVIDIA) differs by an ulp,
      // which a near-tangent quadric hit can magnify past the tolerance:
      // allowed as rarely as the ties above.
      const bool near = std::fabs(hits[i].t - ref[i].t) <= 1e-5f * std::max(1.0f, ref[i].t) &&
                        std::fabs(hits[i].u - ref[i].u) <= 1e-4f * std::max(1.0f, std::fabs(ref[i].u)) &&
                        std::fabs(hits[i].v - ref[i].v) <= 1e-4f * std::max(1.0f, std::fabs(ref[i].v));
      if (!near && ++off <= 3)
        first_off << "\n  ray " << i << " (primitive " << prim << "): t " << hits[i].t << " u " << hits[i].u << " v "
                  << hits[i].v << ", host t " << ref[i].t << " u " << ref[i].u << " v " << ref[i].v;
    }
    EXPECT_LE(differ, set->size() / 10000) << differ << " of " << set->size() << " rays hit another primitive";
    EXPECT_LE(off, set->size() / 10000) << off << " of " << set->size() << " rays hit at another t, u or v:"
                                        << first_off.str();
  }

  std::vector<cl_uint> occluded(shadow.size());
  time_ray_kernel(rt, device_scene, any, "occluded", shadow.origin, shadow.dir, sizeof(cl_uint), 1, occluded.data());
  const std::vector<uint8_t> ref = host_occlusion(tracer, shadow);
  size_t differ = 0, blocked = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    differ += (occluded[i] != 0) != (ref[i] != 0);
    blocked += ref[i];
  }
  EXPECT_LE(differ, ref.size() / 10000);
  EXPECT_GT(blocked, 0u);  // the scene does cast shadows: the test is not vacuous
  EXPECT_LT(blocked, ref.size());
}

// For a cosine-weighted hemisphere, cos(theta) has mean 2/3 and variance
// 1/18, and cos^2(theta) is uniform on [0, 1].
void expect_cosine_distributed(const std::vector<float>& cosines) {
  const double n = double(cosines.size());
  double sum = 0.0;
  std::vector<double> bins(10, 0.0);
  for (float c : cosines) {
    sum += c;
    bins[std::min<size_t>(9, size_t(double(c) * c * 10.0))] += 1.0;
  }
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 5.0 * std::sqrt(1.0 / 18.0 / n));
  double chi2 = 0.0;
  for (double b : bins) chi2 += (b - n / 10.0) * (b - n / 10.0) / (n / 10.0);
  EXPECT_LT(chi2, 33.7);  // 9 degrees of freedom, p = 1e-4
}

TEST(BenchRays, DiffuseRaysAreCosineDistributedOnTheIncomingSide) {
  const Fixture& f = fixture();
  const HostTracer tracer(f.scene, f.bvh);
  std::vector<float> cosines;
  for (size_t k = 0; k < f.rays.diffuse.size(); ++k) {
    const uint32_t i = f.rays.diffuse_source[k];
    const vec3 o = f.rays.primary.o(i), d = f.rays.primary.d(i);
    const HostSurfacePoint sp = tracer.surface_at(f.rays.primary_hits[i], o, d);
    const vec3 facing = dot3(sp.normal, d) < 0.0f ? sp.normal : -sp.normal;
    const vec3 dir = f.rays.diffuse.d(k);
    ASSERT_NEAR(std::sqrt(dot3(dir, dir)), 1.0f, 1e-5f);
    ASSERT_GT(dot3(dir, facing), 0.0f) << "diffuse ray " << k << " leaves into the surface";
    ASSERT_GT(dot3(f.rays.diffuse.o(k) - sp.position, facing), 0.0f) << "origin on the far side, ray " << k;
    ASSERT_EQ(f.rays.diffuse.origin[k].w, 0.0f);
    cosines.push_back(dot3(dir, facing));
  }
  expect_cosine_distributed(cosines);
}

TEST(BenchRays, CosineDirectionForAnyNormal) {
  const vec3 normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, glm::normalize(vec3(0.3f, -0.8f, -0.5f))};
  for (const vec3& n : normals) {
    std::vector<float> cosines;
    for (uint64_t i = 0; i < 20000; ++i) {
      const vec3 d = cosine_direction(n, 99, i);
      ASSERT_GT(dot3(d, n), 0.0f);
      cosines.push_back(dot3(d, n));
    }
    expect_cosine_distributed(cosines);
  }
}

TEST(BenchRays, ShadowRaysAimAtTheFirstLightAndStopShort) {
  const Fixture& f = fixture();
  ASSERT_EQ(f.rays.light, to_vec3(f.scene.lights[0].p0));
  const HostTracer tracer(f.scene, f.bvh);
  ASSERT_TRUE(f.rays.shadow.segments);
  for (size_t k = 0; k < f.rays.shadow.size(); ++k) {
    const vec3 o = f.rays.shadow.o(k), dir = f.rays.shadow.d(k);
    const vec3 to_light = f.rays.light - o;
    const float dist = std::sqrt(dot3(to_light, to_light));
    ASSERT_NEAR(std::sqrt(dot3(dir, dir)), 1.0f, 1e-5f);
    ASSERT_GT(dot3(dir, to_light / dist), 1.0f - 1e-6f) << "shadow ray " << k << " misses the light";
    const float tmax = f.rays.shadow.tmax(k);
    ASSERT_LT(tmax, dist) << "shadow ray " << k << " reaches the light";
    ASSERT_GT(tmax, dist * (1.0f - 2.0f * kShadowEndFraction));
    // It leaves from the side of its surface that faces the light.
    const uint32_t i = f.rays.shadow_source[k];
    const HostSurfacePoint sp = tracer.surface_at(f.rays.primary_hits[i], f.rays.primary.o(i), f.rays.primary.d(i));
    const float side = dot3(sp.normal, f.rays.light - sp.position) >= 0.0f ? 1.0f : -1.0f;
    ASSERT_GT(side * dot3(o - sp.position, sp.normal), 0.0f) << "shadow ray " << k;
  }
}

}  // namespace
}  // namespace caustica
