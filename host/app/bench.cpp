#include "host/app/bench.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "host/bench/bench_rays.h"
#include "host/bench/ray_batch.h"
#include "host/elapsed.h"
#include "host/error.h"

namespace caustica {
namespace {

// One ray kind's figures. Agreement compares the kernel's answer per ray with
// HostTracer's: hit/miss (or occluded/clear) status, and for closest hits
// also the primitive; a ray set that the two disagree on would time a
// different workload than the one the Embree reference traces.
struct KindResult {
  const char* name = "";
  size_t rays = 0;
  double ms = 0.0;
  double hit_fraction = 0.0;      // of the kernel's answers: hit / occluded
  double status_agreement = 1.0;  // hit/miss matches the host trace
  double prim_agreement = 1.0;    // closest hits: same primitive (misses count as matching)
  double check_ms = 0.0;          // host reference trace
  double mrays() const { return ms > 0.0 ? double(rays) / (ms * 1e3) : 0.0; }
};

KindResult time_closest(Session& session, StageKernel& kernel, const char* name, const RaySet& rays,
                        const std::vector<Hit>* known_hits, const HostTracer& tracer, int repetitions) {
  KindResult r;
  r.name = name;
  r.rays = rays.size();
  if (rays.size() == 0) return r;
  std::vector<Hit> hits(rays.size());
  r.ms = time_ray_kernel(*session.runtime, *session.device_scene, kernel, "hits", rays.origin, rays.dir, sizeof(Hit),
                         repetitions, hits.data(), session.settings.local_size);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Hit> computed;
  if (!known_hits) computed = host_closest_hits(tracer, rays);
  const std::vector<Hit>& ref = known_hits ? *known_hits : computed;
  r.check_ms = ms_since(t0);
  size_t hit = 0, same_status = 0, same_prim = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const uint32_t prim = hits[i].prim;
    hit += prim != PRIM_NONE;
    same_status += (prim != PRIM_NONE) == is_hit(ref[i]);
    same_prim += prim == ref[i].prim;
  }
  r.hit_fraction = double(hit) / double(rays.size());
  r.status_agreement = double(same_status) / double(rays.size());
  r.prim_agreement = double(same_prim) / double(rays.size());
  return r;
}

KindResult time_shadow(Session& session, StageKernel& kernel, const RaySet& rays, const HostTracer& tracer,
                       int repetitions) {
  KindResult r;
  r.name = "shadow";
  r.rays = rays.size();
  if (rays.size() == 0) return r;
  std::vector<cl_uint> occluded(rays.size());
  r.ms = time_ray_kernel(*session.runtime, *session.device_scene, kernel, "occluded", rays.origin, rays.dir,
                         sizeof(cl_uint), repetitions, occluded.data(), session.settings.local_size);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint8_t> ref = host_occlusion(tracer, rays);
  r.check_ms = ms_since(t0);
  size_t hit = 0, same = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hit += occluded[i] != 0;
    same += (occluded[i] != 0) == (ref[i] != 0);
  }
  r.hit_fraction = double(hit) / double(rays.size());
  r.status_agreement = r.prim_agreement = double(same) / double(rays.size());
  return r;
}

void print_kind(const KindResult& r, int repetitions) {
  if (r.rays == 0) {
    std::printf("%-7s rays   none (%s)\n", r.name,
                std::strcmp(r.name, "shadow") == 0 ? "the scene has no point light" : "no primary hit");
    return;
  }
  std::printf("%-7s rays   %.2f Mrays/s (%zu rays, median %.2f ms of %d; %s %.1f%%)\n", r.name, r.mrays(), r.rays,
              r.ms, repetitions, std::strcmp(r.name, "shadow") == 0 ? "occluded" : "hit", 100.0 * r.hit_fraction);
  const bool shadow = std::strcmp(r.name, "shadow") == 0;
  std::printf("               agrees with the host trace: status %.4f%%", 100.0 * r.status_agreement);
  if (!shadow) std::printf(", primitive %.4f%%", 100.0 * r.prim_agreement);
  std::printf(" (check %.0f ms)\n", r.check_ms);
}

}  // namespace

int run_bench(BenchArgs& a) {
  a.session.mode = parse_render_mode(a.mode);
  // Cold kernel build time: measured without our cache, and without PoCL's
  // own binary cache (~/.cache/pocl), which would otherwise turn a "cold"
  // build into a 50 ms cache hit. An explicit POCL_KERNEL_CACHE wins.
  a.session.use_kernel_cache = false;
  a.session.profile_stages = true;
  if (a.session.spp == 0) a.session.spp = 16;  // path: a timed render of 16 passes
  setenv("POCL_KERNEL_CACHE", "0", /*overwrite=*/0);
  const auto session = prepare_session(a.session);
  const Scene& s = session->scene;
  const int width = session->settings.width, height = session->settings.height;
  Renderer& renderer = *session->renderer;

  auto t0 = std::chrono::steady_clock::now();
  const BenchRays rays = generate_bench_rays(s, session->bvh, width, height);
  const double ray_generation_ms = ms_since(t0);
  const HostTracer tracer(s, session->bvh);

  // intersect_closest straight from the renderer's program; the any-hit
  // kernel lives in its own small program (kernels/bench/), built with the
  // same feature flags so trace_any is compiled exactly as in the renderer.
  StageKernel closest(session->program.program, "intersect_closest");
  const BuiltProgram shadow_program =
      session->runtime->build_file("bench/trace_shadow_only.cl", session->features.build_options());
  StageKernel any(shadow_program.program, "trace_shadow_only");

  const KindResult primary =
      time_closest(*session, closest, "primary", rays.primary, &rays.primary_hits, tracer, a.repetitions);
  const KindResult diffuse = time_closest(*session, closest, "diffuse", rays.diffuse, nullptr, tracer, a.repetitions);
  const KindResult shadow = time_shadow(*session, any, rays.shadow, tracer, a.repetitions);

  // Untimed first render: with PoCL's cache off, it compiles the stage
  // kernels for their launch shapes.
  renderer.render(nullptr);
  std::vector<double> render_ms;
  RenderStats last;
  for (int r = 0; r < a.repetitions; ++r) {
    RenderStats stats;
    renderer.render(&stats);
    render_ms.push_back(stats.render_ms);
    last = stats;
  }
  std::sort(render_ms.begin(), render_ms.end());
  const double render_median = render_ms[render_ms.size() / 2];

  std::printf("scene          %s (%zu spheres, %zu cylinders, %zu triangles, %zu lights)\n", s.source_path.c_str(),
              s.spheres.size(), s.cylinders.size(), s.triangles.size(), s.light_count());
  std::printf("device         %s\n", session->runtime->device_info().name.c_str());
  std::printf("image          %dx%d, %s\n", width, height, session->features.describe().c_str());
  std::printf("launches       one per ray kind, local size %zu, warm-up launch then median of %d\n",
              session->settings.local_size, a.repetitions);
  std::printf("bvh build      %.2f ms (%zu nodes, SAH %.2f)\n", session->bvh.build_ms, session->bvh.nodes.size(),
              session->bvh.sah_cost);
  const WideBvh& wide = session->wide;
  std::printf("wide bvh       %.2f ms collapse (%zu nodes, %zu leaves, %zu triangle blocks %.0f%% full, %zu other "
              "refs, height %d; SAH %.3f = nodes %.3f + leaves %.3f)\n",
              wide.collapse_ms, wide.nodes.size(), wide.leaves, wide.triangle_blocks.size(),
              wide.triangle_blocks.empty() ? 0.0 : 100.0 * wide.triangle_lanes / (4.0 * wide.triangle_blocks.size()),
              wide.prim_refs.size(), wide.height, wide.node_sah + wide.leaf_sah, wide.node_sah, wide.leaf_sah);
  std::printf("kernel build   %.1f ms (cold; bench any-hit program %.1f ms)\n", session->program.build_ms,
              shadow_program.build_ms);
  std::printf("ray sets       generated on the host in %.0f ms (shared with caustica_embree_bench)\n",
              ray_generation_ms);
  print_kind(primary, a.repetitions);
  print_kind(diffuse, a.repetitions);
  print_kind(shadow, a.repetitions);
  // What the render's own rays cost at the throughputs measured above
  // (secondary rays at the diffuse rate): the render's overhead over pure
  // traversal is shading, ray generation, film work and host round trips.
  auto ms_at = [](uint64_t rays, const KindResult& k) { return k.mrays() > 0.0 ? double(rays) / (k.mrays() * 1e3) : 0.0; };
  const double traversal_ms =
      ms_at(last.camera_rays, primary) + ms_at(last.secondary_rays, diffuse) + ms_at(last.shadow_rays, shadow);
  std::printf("render         %.1f ms (median of %d after a warm-up render)\n", render_median, a.repetitions);
  std::printf("               %llu camera + %llu secondary + %llu shadow rays; %.1f ms of traversal at the rates "
              "above (render / traversal %.2f)\n",
              (unsigned long long)last.camera_rays, (unsigned long long)last.secondary_rays,
              (unsigned long long)last.shadow_rays, traversal_ms, traversal_ms > 0 ? render_median / traversal_ms : 0.0);
  const double per_pass = last.passes > 0 ? 1.0 / last.passes : 0.0;
  std::printf("host traffic   %llu launches, %llu blocking transfers, %llu count reads (non-blocking, waited for "
              "iterations later) for %d passes: %.2f launches, %.2f blocking transfers and %.2f count reads a pass\n",
              (unsigned long long)last.launches, (unsigned long long)last.blocking_transfers,
              (unsigned long long)last.count_reads, last.passes, double(last.launches) * per_pass,
              double(last.blocking_transfers) * per_pass, double(last.count_reads) * per_pass);
  double device_ms = 0.0;
  std::string stages;
  for (const auto& [name, ms] : last.stage_ms) {
    device_ms += ms;
    char part[96];
    std::snprintf(part, sizeof part, "%s%s %.1f", stages.empty() ? "" : ", ", name.c_str(), ms);
    stages += part;
  }
  std::printf("               device time per stage (ms): %s; host and transfers %.1f ms\n", stages.c_str(),
              render_median - device_ms);
  const bool path = session->mode == RenderMode::Path;
  const double samples_per_s = double(width) * height * last.passes / (render_median * 1e-3);
  const double render_mrays = double(last.rays()) / (render_median * 1e3);
  if (path)
    std::printf("path           %.3g samples/s, %.2f Mrays/s (%d spp, %llu rays: camera, continuation and shadow)\n",
                samples_per_s, render_mrays, last.passes, (unsigned long long)last.rays());
  const PhotonGatherStats& g = last.photon_gathers;
  const bool photons = last.photon_rays > 0;
  auto per = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
  if (photons) {
    std::printf("photons        %llu photon rays, %llu stored, %u a pass at the end\n",
                (unsigned long long)last.photon_rays, (unsigned long long)last.photons_stored, last.photons_per_pass);
    std::printf("               visible-point gathers %llu: %.1f photons visited each (99th percentile <= %.0f); "
                "later-receiver gathers %llu: %.1f each (99th percentile <= %.0f)\n",
                (unsigned long long)g.gathers_d1, per(g.visits_d1, g.gathers_d1),
                PhotonGatherStats::quantile(g.histogram_d1, 0.99), (unsigned long long)g.gathers_later,
                per(g.visits_later, g.gathers_later), PhotonGatherStats::quantile(g.histogram_later, 0.99));
    if (!last.caustics_decision.empty()) std::printf("               %s\n", last.caustics_decision.c_str());
  }
  nlohmann::json j = {{"scene", s.source_path},
                      {"device", session->runtime->device_info().name},
                      {"width", width},
                      {"height", height},
                      {"primitives", s.primitive_count()},
                      {"triangles", s.triangles.size()},
                      {"build_ms", session->bvh.build_ms},
                      {"collapse_ms", wide.collapse_ms},
                      {"wide_nodes", wide.nodes.size()},
                      {"wide_sah", wide.node_sah + wide.leaf_sah},
                      {"kernel_build_ms", session->program.build_ms},
                      {"local_size", session->settings.local_size},
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
                      {"ray_generation_ms", ray_generation_ms},
                      {"render_ms", render_median},
                      {"render_traversal_ms", traversal_ms},
                      {"render_launches", last.launches},
                      {"render_blocking_transfers", last.blocking_transfers},
                      {"render_count_reads", last.count_reads},
                      {"render_passes", last.passes},
                      {"render_stage_ms", last.stage_ms}};
  if (path) {
    j["path_samples_per_s"] = samples_per_s;
    j["path_mrays"] = render_mrays;
    j["path_spp"] = last.passes;
  }
  if (photons) {
    j["photon_rays"] = last.photon_rays;
    j["photons_stored"] = last.photons_stored;
    j["photons_per_pass"] = last.photons_per_pass;
    j["gathers_d1"] = g.gathers_d1;
    j["visits_per_gather_d1"] = per(g.visits_d1, g.gathers_d1);
    j["visits_p99_d1"] = PhotonGatherStats::quantile(g.histogram_d1, 0.99);
    j["gathers_later"] = g.gathers_later;
    j["visits_per_gather_later"] = per(g.visits_later, g.gathers_later);
    j["visits_p99_later"] = PhotonGatherStats::quantile(g.histogram_later, 0.99);
    j["caustics_decision"] = last.caustics_decision;
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace caustica
