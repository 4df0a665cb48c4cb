// caustica_embree_bench: the Embree 3 reference for `caustica bench`.
//
// Loads a scene with caustica's loader, generates exactly the rays that
// `caustica bench` traces (host/bench/bench_rays.h: primary, diffuse and
// shadow rays from the same host code, RNG seed and image size), builds an
// Embree scene from the same primitives and times rtcIntersect1 /
// rtcOccluded1 over --threads host threads. Prints the same JSON keys as
// `caustica bench` on its last line, and how often Embree's hit/miss answers
// agree with caustica's host trace (it should be > 99.9%: the two differ
// only in rounding on edges and at grazing angles).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <vector>

#include "bench/embree/embree_scene.h"
#include "host/accel/bvh.h"
#include "host/app/session.h"
#include "host/bench/bench_rays.h"
#include "host/error.h"
#include "host/scene/load_scene.h"

using namespace caustica;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One warm-up run (first-touch of Embree's BVH pages, thread start-up), then
// the median of `repetitions` timed runs.
double median_ms(int repetitions, const std::function<void()>& run) {
  run();
  std::vector<double> times;
  for (int r = 0; r < std::max(1, repetitions); ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    times.push_back(ms_since(t0));
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct KindResult {
  const char* name = "";
  size_t rays = 0;
  double ms = 0.0;
  double hit_fraction = 0.0;
  double status_agreement = 1.0;  // hit/miss (occluded/clear) as in caustica's host trace
  double prim_agreement = 1.0;    // closest hits: same primitive too
  double mrays() const { return ms > 0.0 ? double(rays) / (ms * 1e3) : 0.0; }
};

KindResult closest_kind(const char* name, const EmbreeScene& embree, const RaySet& rays,
                        const std::vector<Hit>& reference, int threads, int repetitions) {
  KindResult r;
  r.name = name;
  r.rays = rays.size();
  if (rays.size() == 0) return r;
  std::vector<uint32_t> prims;
  r.ms = median_ms(repetitions, [&] { embree.trace_closest(rays, threads, &prims); });
  size_t hit = 0, same_status = 0, same_prim = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hit += prims[i] != PRIM_NONE;
    same_status += (prims[i] != PRIM_NONE) == is_hit(reference[i]);
    same_prim += prims[i] == reference[i].prim;
  }
  r.hit_fraction = double(hit) / double(rays.size());
  r.status_agreement = double(same_status) / double(rays.size());
  r.prim_agreement = double(same_prim) / double(rays.size());
  return r;
}

KindResult shadow_kind(const EmbreeScene& embree, const RaySet& rays, const std::vector<uint8_t>& reference,
                       int threads, int repetitions) {
  KindResult r;
  r.name = "shadow";
  r.rays = rays.size();
  if (rays.size() == 0) return r;
  std::vector<uint8_t> occluded;
  r.ms = median_ms(repetitions, [&] { embree.trace_occluded(rays, threads, &occluded); });
  size_t hit = 0, same = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hit += occluded[i];
    same += occluded[i] == reference[i];
  }
  r.hit_fraction = double(hit) / double(rays.size());
  r.status_agreement = r.prim_agreement = double(same) / double(rays.size());
  return r;
}

void print_kind(const KindResult& r, int repetitions) {
  if (r.rays == 0) {
    std::printf("%-7s rays   none\n", r.name);
    return;
  }
  const bool shadow = r.name[0] == 's';
  std::printf("%-7s rays   %.2f Mrays/s (%zu rays, median %.2f ms of %d; %s %.1f%%)\n", r.name, r.mrays(), r.rays,
              r.ms, repetitions, shadow ? "occluded" : "hit", 100.0 * r.hit_fraction);
  std::printf("               agrees with caustica's host trace: status %.4f%%", 100.0 * r.status_agreement);
  if (!shadow) std::printf(", primitive %.4f%%", 100.0 * r.prim_agreement);
  std::printf("\n");
  if (r.status_agreement < 0.999)
    std::fprintf(stderr, "caustica_embree_bench: warning: %s rays agree on only %.4f%% (expected > 99.9%%)\n", r.name,
                 100.0 * r.status_agreement);
}

struct Args {
  std::string scene_path;
  int width = 0, height = 0;
  int repetitions = 5;
  int threads = 2;
  std::string build = "high";
};

int run(const Args& a) {
  auto t0 = std::chrono::steady_clock::now();
  const Scene scene = load_scene(a.scene_path);
  const double load_ms = ms_since(t0);
  int width = 0, height = 0;
  resolve_image_size(scene.camera, a.width, a.height, &width, &height);

  // caustica's BVH is needed for the shared ray generator and the host
  // reference trace, not for Embree.
  const Bvh bvh = build_bvh(scene);
  t0 = std::chrono::steady_clock::now();
  const BenchRays rays = generate_bench_rays(scene, bvh, width, height);
  const double ray_generation_ms = ms_since(t0);
  const HostTracer tracer(scene, bvh);
  t0 = std::chrono::steady_clock::now();
  const std::vector<Hit> diffuse_reference = host_closest_hits(tracer, rays.diffuse);
  const std::vector<uint8_t> shadow_reference = host_occlusion(tracer, rays.shadow);
  const double check_ms = ms_since(t0);

  const RTCBuildQuality quality = a.build == "medium" ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
  const EmbreeScene embree(scene, a.threads, quality);
  const KindResult primary = closest_kind("primary", embree, rays.primary, rays.primary_hits, a.threads,
                                          a.repetitions);
  const KindResult diffuse = closest_kind("diffuse", embree, rays.diffuse, diffuse_reference, a.threads,
                                          a.repetitions);
  const KindResult shadow = shadow_kind(embree, rays.shadow, shadow_reference, a.threads, a.repetitions);

  std::printf("scene          %s (%zu spheres, %zu cylinders, %zu triangles, %zu lights; loaded in %.0f ms)\n",
              scene.source_path.c_str(), scene.spheres.size(), scene.cylinders.size(), scene.triangles.size(),
              scene.light_count(), load_ms);
  std::printf("tracer         Embree %s, rtcIntersect1/rtcOccluded1 on %d threads, build quality %s%s\n",
              RTC_VERSION_STRING, a.threads, a.build.c_str(),
              scene.spheres.empty() && scene.cylinders.empty() ? "" : ", spheres/cylinders as user geometry");
  std::printf("image          %dx%d\n", width, height);
  std::printf("bvh build      %.2f ms (rtcCommitScene; geometry setup %.2f ms)\n", embree.build_ms(),
              embree.setup_ms());
  std::printf("ray sets       generated on the host in %.0f ms, host reference trace %.0f ms\n", ray_generation_ms,
              check_ms);
  print_kind(primary, a.repetitions);
  print_kind(diffuse, a.repetitions);
  print_kind(shadow, a.repetitions);
  nlohmann::json j = {{"scene", scene.source_path},
                      {"tracer", std::string("embree ") + RTC_VERSION_STRING},
                      {"threads", a.threads},
                      {"build_quality", a.build},
                      {"width", width},
                      {"height", height},
                      {"primitives", scene.primitive_count()},
                      {"triangles", scene.triangles.size()},
                      {"build_ms", embree.build_ms()},
                      {"setup_ms", embree.setup_ms()},
                      {"repetitions", a.repetitions},
                      {"primary_mrays", primary.mrays()},
                      {"diffuse_mrays", diffuse.mrays()},
                      {"shadow_mrays", shadow.mrays()},
                      {"primary_rays", primary.rays},
                      {"diffuse_rays", diffuse.rays},
                      {"shadow_rays", shadow.rays},
                      {"primary_agreement", primary.status_agreement},
                      {"diffuse_agreement", diffuse.status_agreement},
                      {"shadow_agreement", shadow.status_agreement},
                      {"primary_prim_agreement", primary.prim_agreement},
                      {"diffuse_prim_agreement", diffuse.prim_agreement},
                      {"ray_generation_ms", ray_generation_ms}};
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"caustica_embree_bench: Embree reference for `caustica bench` (same scene, same rays)"};
  Args a;
  app.add_option("scene", a.scene_path, "scene JSON file")->required();
  app.add_option("--width", a.width, "image width (default: the camera's)");
  app.add_option("--height", a.height, "image height");
  app.add_option("--repetitions", a.repetitions, "timed repetitions (median)")->check(CLI::PositiveNumber);
  app.add_option("--threads", a.threads, "tracing and build threads")->check(CLI::PositiveNumber);
  app.add_option("--build", a.build,
                 "Embree build quality: high (spatial splits, the reference) or medium (rtcNewScene's default)")
      ->check(CLI::IsMember({"high", "medium"}));
  CLI11_PARSE(app, argc, argv);
  try {
    return run(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "caustica_embree_bench: error: %s\n", e.what());
    return 1;
  }
}
