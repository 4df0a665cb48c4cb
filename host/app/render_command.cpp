// `caustica render`, the run: what the options and the prepared scene decide
// (plan_render: the resumed state, the reference, the session, the checks
// that need its mode and settings, the denoiser), the render in this process
// or across mpirun's ranks, then what it writes (render_outputs.cpp). The
// options and their checks: render_options.cpp.
#include "host/app/render_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <thread>

#include "host/app/distributed_render.h"
#include "host/app/render_stages.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/lights/light_types.h"

namespace caustica {
namespace {

// The option that asks for the film's aux passes (albedo, normal, depth).
std::string aux_pass_option(const RenderArgs& a) {
  return a.denoise ? "--denoise" : !a.aov_dir.empty() ? "--aov-dir" : "an .exr output";
}

// A state that cannot be read, or is damaged, fails before the scene is read.
std::optional<RenderState> read_resume_state(RenderArgs& a) {
  if (a.resume.empty() && !a.resume_state) return std::nullopt;
  if (a.resume.empty()) a.resume = "the resumed state";
  RenderState state = a.resume_state ? *a.resume_state : read_render_state(a.resume);
  // A state made with the aux passes resumes with them (whatever this
  // render's outputs); one made without cannot give them.
  for (const auto& [name, value] : state.identity)
    if (name == "aux passes") {
      if (value == "on") a.session.aux_passes = true;
      else if (a.session.aux_passes)
        throw Error(a.resume + ": a state rendered without the aux passes (albedo, normal, depth), which " +
                    aux_pass_option(a) + " needs: write a .pfm or .png, or render again");
    }
  return state;
}

// A bad reference fails before anything is built or rendered.
std::optional<ImageF> read_reference(const RenderArgs& a) {
  if (a.reference.empty()) return std::nullopt;
  if (!is_hdr_path(a.reference)) throw Error("--reference " + a.reference + ": expected a linear .pfm or .exr image");
  try {
    return read_hdr_image(a.reference);
  } catch (const Error& e) {
    throw Error("--reference: " + std::string(e.what()));
  }
}

// What needs the session's size or mode, known once the scene is read.
void check_against_session(const RenderArgs& a, const Session& session, const std::optional<ImageF>& reference) {
  if (reference && (reference->width != session.settings.width || reference->height != session.settings.height))
    throw Error("--reference " + a.reference + ": the reference is " + std::to_string(reference->width) + "x" +
                std::to_string(reference->height) + " but the render is " + std::to_string(session.settings.width) +
                "x" + std::to_string(session.settings.height) + " (set --width/--height to match)");
  if (a.target_error > 0.0 && session.mode != RenderMode::Path)
    throw Error("--target-error: only path mode is stochastic; binary and phong images are exact after one pass");
  if (!a.spp_map.empty() && session.mode != RenderMode::Path)
    throw Error("--spp-map: only path mode takes several samples a pixel");
  if ((a.denoise || !a.aov_dir.empty()) && session.mode != RenderMode::Path)
    throw Error(aux_pass_option(a) + ": path mode only (binary and phong images are exact, with no noise and no passes)");
}

std::unique_ptr<Denoiser> make_denoiser(const RenderArgs& a, const DeviceInfo& device) {
  DenoiserOptions options;
  options.quality = parse_denoise_quality(a.denoise_quality);
  options.gpu = device.type == "gpu";
  // OIDN's threads are the render's: an OpenCL CPU device's compute units
  // (PoCL's threads, which POCL_MAX_PTHREAD_COUNT limits).
  options.threads = device.type == "cpu" && device.compute_units > 0
                        ? int(device.compute_units)
                        : std::max(1, int(std::thread::hardware_concurrency()));
  auto denoiser = std::make_unique<Denoiser>(options);
  if (a.verbose) std::fprintf(stderr, "[caustica] denoiser: %s\n", denoiser->description().c_str());
  return denoiser;
}

// A range of passes rendered alone (--passes) holds none of what adaptive
// sampling and the photon pass need of the whole film. (Ranks share every
// wave instead, distributed_render.h: nothing to refuse there.)
void check_pass_split(const RenderArgs& a, const Session& session) {
  if (a.passes.empty()) return;
  if (session.mode != RenderMode::Path)
    throw Error("--passes " + a.passes + ": only path mode takes several passes (binary and phong take one)");
  if (session.settings.caustics)
    throw Error("--passes " + a.passes + ": the photon pass (--caustics " +
                std::string(a.session.caustics == CausticsMode::On ? "on" : "auto, which found caustics here") +
                ") keeps per-pixel statistics that are not sums of passes (each photon map's gather updates those "
                "the maps before it left): add --caustics off, or render on mpirun's ranks, which keep the photon "
                "pass (docs/distributed.md)");
}

// What a resumed state must match, and what a checkpoint records.
StateIdentity state_identity(const RenderArgs& a, const Session& session, bool resuming) {
  if (a.checkpoint.empty() && !resuming) return {};
  return render_identity(scene_hash(session.scene), session.mode, session.settings,
                         bvh_quality_name(a.session.bvh_quality));
}

void check_resumed_state(const RenderArgs& a, const Session& session, const RenderState& resume,
                         const StateIdentity& identity) {
  check_render_state(a.resume, resume, identity);
  try {
    session.renderer->check_state(resume);
  } catch (const Error& e) {
    throw Error(a.resume + ": " + e.what());
  }
  // The pass range (a state of passes [2, 4) resumed to --spp 4 wrote a
  // 2-spp image) and the sampler's state: Renderer::check_state.
}

// Path tracing never reaches a point or spot light through glass or in a mirror:
// without the photon pass those caustics are missing, and the error
// estimate, which sees only noise, cannot tell.
void warn_missing_caustics(const RenderArgs& a, const Session& session) {
  if (!a.quiet && session.mode == RenderMode::Path && a.session.caustics == CausticsMode::Off &&
      has_delta_light(session.scene) && analyse_scene(session.scene, RenderMode::Path, CausticsMode::Auto).caustics)
    std::fprintf(stderr,
                 "[caustica] warning: --caustics off: the caustics of this scene's point and spot lights (through glass, in "
                 "mirrors) are missing from the image, and from its error estimate\n");
}

// -v: the scene, the kernels and the device the render runs with.
void describe_session(const RenderArgs& a, const Session& session) {
  const Scene& scene = session.scene;
  std::fprintf(stderr, "[caustica] scene %s: %zu spheres, %zu cylinders, %zu triangles, %zu lights, %zu materials (load %.1f ms)\n",
               scene.source_path.c_str(), scene.spheres.size(), scene.cylinders.size(), scene.triangles.size(),
               scene.light_count(), scene.materials.size(), session.load_ms);
  for (const auto& m : scene.meshes)
    std::fprintf(stderr, "[caustica] mesh %s: %zu triangles (%zu degenerate dropped), loaded in %.1f ms\n",
                 m.file.c_str(), m.triangles, m.dropped_degenerate, m.load_ms);
  std::fprintf(stderr, "[caustica] features: %s\n[caustica] kernel options:%s\n", session.features.describe().c_str(),
               session.features.build_options().c_str());
  std::fprintf(stderr, "[caustica] device: %s (%s)\n", session.runtime->device_info().name.c_str(),
               session.runtime->device_info().platform_name.c_str());
  if (session.mode == RenderMode::Path)
    std::fprintf(stderr, "[caustica] light sampler: %s (--light-sampler %s; auto picks the tree above %zu lights)\n",
                 light_sampler_name(session.settings.light_sampler), light_sampler_name(a.session.light_sampler),
                 kLightTreeThreshold);
  if (session.mode == RenderMode::Path)
    std::fprintf(stderr, "[caustica] kernel shape: %s (--kernel-shape %s)\n",
                 kernel_shape_name(session.settings.kernel_shape), kernel_shape_name(a.session.kernel_shape));
  std::fprintf(stderr, "[caustica] kernel build: %.1f ms (%s)\n", session.program.build_ms,
               session.program.cache_state());
  std::fprintf(stderr, "[caustica] BVH build: %.2f ms, %zu nodes, SAH cost %.2f, depth %d\n", session.bvh.build_ms,
               session.bvh.nodes.size(), session.bvh.sah_cost, session.bvh.max_depth);
}

DisplaySettings display_settings(const RenderArgs& a, const Session& session) {
  DisplaySettings display;
  display.tonemap = parse_tonemap(!a.tonemap.empty() ? a.tonemap
                                                     : session.mode == RenderMode::Path ? "aces" : "linear");
  display.exposure_scale = std::exp2(a.exposure ? *a.exposure : session.scene.camera.exposure);
  display.gamma = a.gamma ? *a.gamma : session.mode == RenderMode::Path ? kPathDisplayGamma : kCourseworkDisplayGamma;
  return display;
}

// Everything the options and the prepared scene decide, each refusal before
// the first sample.
RenderPlan plan_render(RenderArgs& a) {
  RenderPlan plan;
  plan.distributed = a.ranks && a.ranks->size() > 1;
  plan.resume = read_resume_state(a);
  plan.reference = read_reference(a);
  a.session.error_estimate = !a.no_error_estimate;
  if (a.no_error_estimate) a.session.adaptive = false;  // it allocates by that estimate
  a.session.open_ended = a.target_error > 0.0;
  plan.session = prepare_session(a.session);
  const Session& session = *plan.session;
  check_against_session(a, session, plan.reference);
  if (!a.aov_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.aov_dir, ec);
    if (ec) throw Error("--aov-dir " + a.aov_dir + ": cannot create it: " + ec.message());
  }
  if (a.denoise) plan.denoiser = make_denoiser(a, session.runtime->device_info());
  check_pass_split(a, session);
  plan.identity = state_identity(a, session, plan.resume.has_value());
  if (plan.resume) check_resumed_state(a, session, *plan.resume, plan.identity);
  plan.resumed_passes = plan.resume ? plan.resume->film.passes : 0;
  warn_missing_caustics(a, session);
  if (a.verbose) describe_session(a, session);
  plan.display = display_settings(a, session);
  // Guides noisy in kind: a lens, or smooth glass splitting paths.
  plan.guides = a.denoise_guides == "auto"
                    ? guide_mode_for(session.scene.camera.aperture_radius > 0.0f, session.features.refraction)
                    : parse_guide_mode(a.denoise_guides);
  return plan;
}

ErrorMonitorOptions error_monitor_options(const RenderArgs& a, RenderPlan& plan) {
  ErrorMonitorOptions options;
  options.report_path = a.report;
  options.plot_path = a.plot;
  options.reference = std::move(plan.reference);
  options.target_error = a.target_error;
  // Ranks sum their films for every measurement: with only a target error
  // to watch, measure from 16 passes on where it is projected (1.43 s of a
  // 24 s Cornell box render on 2 ranks went to 8 geometric ones).
  if (plan.distributed && a.target_error > 0.0 && a.report.empty() && a.plot.empty() && !options.reference)
    options.sparse_from = 16;
  options.exposure_scale = plan.display.exposure_scale;
  options.header = report_header(*plan.session, a, plan.resumed_passes);
  options.denoiser = plan.denoiser.get();
  options.guides = plan.guides;
  return options;
}

// One process: after every pass the error monitor decides whether to go on,
// the outputs due while rendering are written, and a caller keeping the
// render in memory may stop it (RenderArgs::on_wave).
RenderResult render_in_process(const RenderArgs& a, RenderRun& run, ProgressReporter& progress,
                               RenderOutputs& outputs) {
  RenderResult result;
  RenderPlan& plan = run.plan;
  ErrorMonitor& monitor = *run.monitor;
  Renderer& renderer = *plan.session->renderer;
  result.shown = &renderer;
  result.image = renderer.render(
      &run.stats, [&](const PassProgress& p) { progress.update(p); },
      [&](const Film& film, double seconds) {
        result.seconds = seconds;
        const bool go_on = monitor.on_pass(film, seconds);
        outputs.on_pass(renderer, film, seconds);
        if (go_on && a.on_wave && !a.on_wave(WaveDone{film.passes(), seconds, monitor.estimate()})) {
          run.stopped_by_caller = true;
          return false;
        }
        return go_on;
      },
      plan.resume ? &*plan.resume : nullptr);
  return result;
}

// mpirun's ranks (host/app/distributed_render.h): rank 0 sums their films,
// and alone reports, measures, checkpoints and writes. Nothing on the others.
std::optional<RenderResult> render_on_ranks(const RenderArgs& a, RenderPlan& plan, RenderStats& stats,
                                            ProgressReporter& progress, ErrorMonitor& monitor,
                                            RenderOutputs& outputs) {
  RankGroup& ranks = *a.ranks;
  const bool root = ranks.rank() == 0;
  // Rounds wait for the monitor's decisions only when it has something to decide.
  const bool monitored = !a.report.empty() || !a.reference.empty() || a.target_error > 0.0;
  DistributedOutputs due;
  if (!a.checkpoint.empty()) {
    due.checkpoint_every_s = a.checkpoint_every_s.value_or(kDefaultCheckpointSeconds);
    due.checkpoint = [&outputs](const Renderer& renderer) { outputs.write_checkpoint(renderer); };
  }
  if (a.write_every_s > 0.0) {
    due.write_every_s = a.write_every_s;
    due.write = [&outputs](const Renderer& summed, double) { outputs.write_images(summed.film().mean(), summed.film()); };
  }
  DistributedResult summed = render_distributed(
      *plan.session, ranks, &stats,
      root ? ProgressCallback([&](const PassProgress& p) { progress.update(p); }) : ProgressCallback{},
      root && monitored ? &monitor : nullptr, plan.resume ? &*plan.resume : nullptr, due);
  if (!root) return std::nullopt;
  RenderResult result;
  result.image = std::move(summed.image);
  result.summed = std::move(summed.summed);
  result.shown = result.summed.get();
  result.seconds = summed.seconds;
  stats.render_ms = summed.seconds * 1e3;
  if (a.verbose)
    std::fprintf(stderr,
                 "[caustica] %d ranks: %s summed on rank 0 in %d reductions, %.3f s (film reads %.3f s, waiting for "
                 "ranks %.3f s, MPI %.3f s, restore %.3f s); its error measurements %.3f s\n",
                 ranks.size(), result.shown->film().held().describe().c_str(), summed.reductions,
                 summed.reduction_seconds, summed.read_seconds, summed.wait_seconds, summed.mpi_seconds,
                 summed.restore_seconds, summed.measure_seconds);
  if (a.verbose && summed.by_waves && summed.weight_refreshes > 0)
    std::fprintf(stderr,
                 "[caustica] %d ranks: the adaptive sampler's weights refreshed %d times from the summed film, %.3f s "
                 "(colour sums and ray counts summed on every rank: MPI %.3f s; weights on each), after waiting %.3f s "
                 "for the slowest rank\n",
                 ranks.size(), summed.weight_refreshes, summed.weight_seconds, summed.weight_mpi_seconds,
                 summed.weight_wait_seconds);
  if (a.verbose && summed.by_waves && stats.photon_maps > 0)
    std::fprintf(stderr,
                 "[caustica] %d ranks shared the photon pass: %u photon maps gathered to every rank, "
                 "%.0f bytes a map; rank 0 waited %.4f s a map for the slowest rank and gathered in %.4f s a map\n",
                 ranks.size(), stats.photon_maps, double(summed.photon_traffic.bytes) / std::max(1u, stats.photon_maps),
                 summed.photon_traffic.wait_seconds / std::max(1u, stats.photon_maps),
                 summed.photon_traffic.gather_seconds / std::max(1u, stats.photon_maps));
  return result;
}

}  // namespace

std::unique_ptr<RenderRun> render_scene(RenderArgs& a) {
  check_render_options(a);
  auto run = std::make_unique<RenderRun>();
  run->plan = plan_render(a);
  RenderPlan& plan = run->plan;
  ProgressReporter progress(!a.quiet);
  run->monitor = std::make_unique<ErrorMonitor>(error_monitor_options(a, plan));
  ErrorMonitor& monitor = *run->monitor;
  progress.set_error_monitor(&monitor);
  RenderOutputs outputs(a, plan);
  run->result = plan.distributed ? render_on_ranks(a, plan, run->stats, progress, monitor, outputs)
                                 : render_in_process(a, *run, progress, outputs);
  if (!run->result) return run;  // a rank other than 0: rank 0 writes what the ranks rendered
  const RenderResult& result = *run->result;
  progress.finish();
  if (a.write_output) outputs.write_images(result.image, result.shown->film());
  if (!a.checkpoint.empty()) outputs.write_checkpoint(*result.shown);
  monitor.finish(result.shown->film(), result.seconds);
  report_render(a, plan, run->stats, result, monitor);
  return run;
}

int run_render(RenderArgs& a) {
  render_scene(a);
  return 0;
}

}  // namespace caustica
