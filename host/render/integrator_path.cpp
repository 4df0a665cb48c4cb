// Path mode: unidirectional path tracing with next-event estimation and
// BSDF sampling combined by multiple importance sampling (power heuristic),
// Russian roulette, Sobol-Burley samples. Stages: generate_camera_samples ->
// { intersect_closest -> shade_surface_path -> intersect_shadow }*.
//
// Waves: one wave traces several passes of the whole image (wave_passes:
// about kWaveSamples samples) through a fixed number of path slots. The
// generate stage starts the first samples; when a path ends, the shade
// stage starts the wave's next sample in its place (path regeneration,
// Novak et al. 2010), so the queues stay full until the wave's samples run
// out and the launches per sample are few. Two ping-pong path queues (each
// path pushes one record at most, so a queue never overflows), one
// addressed shadow slot per path, and the bounce loop of every integrator
// (host/render/wave_loop.h: counts on the device, read without blocking):
// the host writes nothing between waves or iterations, and launches over
// the slots until the wave's samples have all started; from then on the
// counts only fall, and the first zero ends the wave. The film
// sums in fixed point, so the order in which slots take samples changes no
// bit. With caustics, a PhotonPass traces photons before a pass and
// gathers them after (host/render/photon_pass.h), so a pass that traces a
// map is a wave of one, and the passes up to the next map share one; with
// `--caustics auto` it is kept only where it pays (decide_photon_pass
// below).
#include <algorithm>
#include <cstdio>
#include <string>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/image/metrics.h"
#include "host/render/device_scene.h"
#include "host/render/error_estimate.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"
#include "host/lights/light_table.h"
#include "host/render/photon_pass.h"
#include "host/render/state_bytes.h"
#include "host/render/wave_loop.h"

namespace caustica {
namespace {

// `--caustics auto` measures the photon pass as work, never as wall time,
// so that the decision is the same for a seed and spp on any machine. The
// unit is one ray of a camera path (closest hit with its shading, or a
// shadow ray); the other items are weighed by their device time per item
// against it, measured with `caustica bench scenes/... --caustics on` on
// the 2-core PoCL CPU (official scene.json at 240x160, 16 spp: 83 ns a
// camera-path ray, 94 ns a photon ray with its emission and bounce, 24 ns
// a stored photon's compaction and grid build, 133 ns a visible point's
// gather of ~6 photons, ~200 ns an inline gather in the shade stage).
constexpr double kPhotonRayWork = 1.1;
constexpr double kStoredPhotonWork = 0.3;
constexpr double kVisiblePointGatherWork = 1.5;
constexpr double kLaterGatherWork = 2.4;
constexpr double kVisitWork = 0.05;  // each photon read, beyond a gather's own cost
// The photon pass may take at most this share of a pass's work: the camera
// paths then keep about 65% of their samples per second (issue 19's floor
// is 60%; the weights above are averages).
constexpr double kMostPhotonShare = 0.35;
// Below this share of the image's light, the photon map brings nothing a
// viewer or the error would notice: off.
constexpr double kLeastCausticShare = 1e-3;
// A photon map every this many passes at the most; beyond it, off.
constexpr int kLongestInterval = 64;
// The errors are balanced at the first map after this many passes (the
// half-buffer estimate needs a few).
constexpr int kBalanceAfterPasses = 4;

// A wave holds about this many samples (more passes per wave for smaller
// images, up to Film::kMostWavePasses): at 2-core PoCL speeds about a
// second of work, so the time limit and progress keep their grain, while
// the tail of its last paths (launches over few paths) is amortised.
constexpr size_t kWaveSamples = size_t(1) << 22;
// Russian roulette from this many scattering events on (Mitsuba's default
// too). Measured (issue 20), Cornell box at 128^2, 256 spp against
// Mitsuba's 16384-spp image: relMSE x spp 0.150 / 0.117 / 0.097 / 0.086 /
// 0.076 from 3 / 4 / 5 / 6 / 8. At equal time (5 s, 2 cores, 4 seeds) 5
// against 3: relMSE 2.01e-4 against 2.49e-4 on the Cornell box, 1.53e-3
// against 1.78e-3 on scenes/caustics.json, 1.56e-3 against 2.26e-3 on
// scenes/showcase_path.json (3 seeds each; /tmp script in the issue note).
constexpr uint32_t kRouletteDepth = 5;
// Paths in flight: 224 bytes each (two path records, a hit, a shadow
// record), 56 MiB. On the 2-core PoCL CPU, 2^16 to 2^19 slots render the
// Cornell box at 128^2 and 512^2 within the machine's noise of each other.
constexpr size_t kPathSlots = size_t(1) << 18;

// Owns its light table (Light and the per-primitive light indices), two
// path queues, the hits and the shadow slots, all sized for its path slots.
class PathIntegrator final : public Integrator {
  StageKernel generate_, intersect_, shade_, shadow_stage_;
  StageKernel paths_;  // trace_paths: the CPU shape (settings.kernel_shape)
  size_t light_count_ = 0;
  uint32_t environment_light_ = LIGHT_NONE;  // its index in the light table (PathParams)
  size_t slots_ = 0;  // paths in flight
  DeviceLights lights_;
  cl::Buffer hits_;
  DeviceQueue rays_[2], shadow_;
  // The bounce loop and its counters (host/render/wave_loop.h): extra
  // counter 0 counts the shadow rays traced, 1 is the wave's progress.
  enum { kShadowRays = 0, kWaveProgress = 1 };
  std::unique_ptr<WaveLoop> loop_;
  cl_uint closest_rays_seen_ = 0, shadow_rays_seen_ = 0;  // the counters at the end of the latest wave
  std::unique_ptr<PhotonPass> photons_;  // only with the caustics feature
  cl::Buffer numerics_;                   // only with --check-numerics
  uint64_t pass_rays_ = 0;                // this pass's camera-path rays (closest + shadow)
  std::string decision_;                  // what `auto` decided, for --verbose and the bench
  uint32_t interval_ = 1;                 // a photon map every interval_ passes (`auto` sets it)
  uint32_t least_interval_ = 1;           // the work share's bound on it
  bool balanced_ = false;                 // the errors' balance has set interval_
  uint32_t passes_counted_ = 0;           // passes whose inline gathers the counters hold
  uint32_t passes_since_photons_ = 0;     // 0: this pass traces and gathers a photon map
  bool photon_pass_now_ = false;
  PixelShare* share_ = nullptr;           // waves shared among processes (share_pixels)

  void decide_photon_pass(const Film& film);
  // The wave as whole paths per work-item (trace_paths.cl), one launch.
  bool trace_paths(Film& film, const PathParams& params, const CameraGPU& camera, size_t samples,
                   RenderStats* stats);
  // The shade stage's and trace_paths' arguments after the film (the
  // photon pass's, the numeric counters, the aux passes), in their order.
  // PATH_STAGE_PARAMS (kernels/integrator/path_stage_data.h), which both
  // shapes' kernels take, and the wave's sampling (camera, progress,
  // allocation, the pixels' ray counts): bound here for both.
  void bind_path_stage_data(KernelArgs& args, Film& film, const PathParams& params);
  void bind_wave_sampling(KernelArgs& args, Film& film, const CameraGPU& camera);
  // A wave's closest-hit and shadow rays from the counters at its end
  // (both shapes keep them alike), into pass_rays_ and the stats.
  void count_wave_rays(cl_uint closest_rays, cl_uint shadow_rays, size_t samples, RenderStats* stats);

 public:
  PathIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                 const RenderSettings& settings);
  bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats) override;
  static int most_wave_passes(const Film& film) {
    return int(std::clamp<size_t>(kWaveSamples / std::max<size_t>(1, film.pixel_count()), 1, Film::kMostWavePasses));
  }
  // With the photon pass on, a pass that traces a photon map is a wave of
  // its own (its first receivers record the pixels' visible points); the
  // passes up to the next map may share one.
  int wave_passes(const Film& film) const override {
    const int most = most_wave_passes(film);
    if (!photons_ || (film.passes() > 0 && !photons_->on())) return most;
    if (film.passes() == 0 || passes_since_photons_ == 0) return 1;
    return std::min(most, int(interval_ - passes_since_photons_));
  }
  // The schedule as it stands: a wave that brings the passes since the
  // latest map to interval_ is followed by a map's pass, then the passes up
  // to the next map (`auto` may still change interval_ at that map).
  UnevenWaveGuess next_uneven_wave(const Film& film, int wave) const override {
    const int most = most_wave_passes(film);
    if (!photons_ || !photons_->on()) return {0, most};
    const uint32_t since = (passes_since_photons_ + uint32_t(wave)) % interval_;
    if (since == 0) return {1, std::min(most, int(interval_) - 1)};
    return {0, std::min(most, int(interval_ - since))};
  }
  void begin_pass(Film& film, RenderStats* stats) override {
    if (numerics_() && film.passes() == 0)
      launcher_.runtime().fill(numerics_, cl_ulong(0), 0, NUMERICS_COUNTERS * sizeof(cl_ulong));
    pass_rays_ = 0;
    photon_pass_now_ = false;
    if (!photons_) return;
    if (film.passes() == 0) {
      photons_->clear();
      decision_.clear();
      interval_ = least_interval_ = 1;
      balanced_ = false;
      passes_since_photons_ = passes_counted_ = 0;
    }
    film.set_separate_estimate(photons_.get());
    if (!photons_->on()) return;
    // A new photon map every interval_ passes; the passes between reuse the
    // latest one for their later receivers (photon_pass.h).
    photon_pass_now_ = passes_since_photons_ == 0;
    if (photon_pass_now_) photons_->trace(stats);
  }
  // A wave that traces a photon map records every pixel's visible point:
  // one sample each.
  bool wave_may_be_uneven(const Film& film) const override { return next_pass_kind(film) == 0; }
  int next_pass_kind(const Film& film) const override {
    if (!photons_ || (film.passes() > 0 && !photons_->on())) return 0;
    return film.passes() == 0 || passes_since_photons_ == 0 ? 1 : 0;
  }
  void end_pass(Film& film, int passes, RenderStats* stats) override {
    if (!photons_ || !photons_->on()) return;
    passes_counted_ += uint32_t(passes);
    if (photon_pass_now_) {
      photons_->gather(stats);  // reads the counters of the passes since the last map
      if (settings_.caustics_auto) decide_photon_pass(film);
      passes_counted_ = 0;
    }
    passes_since_photons_ = (passes_since_photons_ + uint32_t(passes)) % interval_;
  }
  // The photon pass's schedule and state (render_state.h); nothing without it.
  std::string state() const override {
    if (!photons_) return {};
    StateWriter out;
    out.put(interval_);
    out.put(least_interval_);
    out.put(uint8_t(balanced_ ? 1 : 0));
    out.put(passes_counted_);
    out.put(passes_since_photons_);
    out.text(decision_);
    photons_->save(out);
    return std::move(out.bytes());
  }
  void restore_state(Film& film, const std::string& bytes, const std::string& what) override {
    if (!photons_) return Integrator::restore_state(film, bytes, what);
    if (bytes.empty()) throw Error(what + ": no photon pass state for a render with the photon pass");
    StateReader in(bytes, 0, bytes.size(), what);
    interval_ = in.get<uint32_t>("photon schedule");
    least_interval_ = in.get<uint32_t>("photon schedule");
    balanced_ = in.get<uint8_t>("photon schedule") != 0;
    passes_counted_ = in.get<uint32_t>("photon schedule");
    passes_since_photons_ = in.get<uint32_t>("photon schedule");
    decision_ = in.text("photon schedule");
    if (interval_ == 0 || passes_since_photons_ >= interval_)
      throw Error(what + ": a photon map every " + std::to_string(interval_) + " passes, " +
                  std::to_string(passes_since_photons_) + " since the latest");
    photons_->load(in);
    if (!in.done()) throw Error(what + ": bytes after the photon pass's state");
    // Added to the image even when no pass is left to run.
    film.set_separate_estimate(photons_.get());
  }
  // Under ranks every wave is shared (docs/distributed.md); the photon pass
  // keeps each pixel's statistics with the process whose window holds it.
  // `auto` decides from the whole image's counts and film, which every
  // process gathers at its three decisions (decide_photon_pass).
  bool share_pixels(PixelShare* share) override {
    share_ = share && share->size() > 1 ? share : nullptr;
    if (photons_) photons_->share(share);
    return true;
  }
  void zero_shared_sums() override {
    if (photons_) photons_->zero_counters();
  }
  void gather_shared_pixels() override {
    if (photons_) photons_->gather_pixels_to_all();
  }
  std::string pixel_slice(bool for_state) const override {
    return photons_ ? photons_->pixel_slice(for_state) : std::string();
  }
  void put_pixel_slices(const std::vector<std::string>& by_rank) override {
    if (photons_) photons_->put_pixel_slices(by_rank);
  }
  SharedPhotonTraffic shared_photon_traffic() const override {
    return photons_ ? photons_->traffic() : SharedPhotonTraffic{};
  }
  void collect(RenderStats* stats) override {
    if (photons_ && stats) {
      photons_->read_counters(stats);
      stats->photon_gathers = photons_->stats().gathers;
      stats->photons_per_pass = photons_->on() ? photons_->photons_per_pass() : 0u;
      stats->photons_stored = photons_->stats().stored;
      stats->photon_seconds = photons_->stats().seconds;
      stats->photon_maps = photons_->photon_passes();
      stats->caustics_decision = decision_;
    }
    if (!numerics_() || !stats) return;
    stats->numerics.assign(NUMERICS_COUNTERS, 0);
    launcher_.runtime().queue().enqueueReadBuffer(numerics_, CL_TRUE, 0, NUMERICS_COUNTERS * sizeof(cl_ulong),
                                                  stats->numerics.data());
  }
};

PathIntegrator::PathIntegrator(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                               const RenderSettings& settings)
    : Integrator("path", launcher, scene, settings),
      generate_(program, "generate_camera_samples"),
      intersect_(program, "intersect_closest"),
      shade_(program, "shade_surface_path"),
      shadow_stage_(program, "intersect_shadow") {
  auto& ctx = launcher.runtime().context();
  const LightTable table = build_light_table(scene.scene());
  // --light-sampler tree or uniform: the tree next-event estimation walks
  // (the program is built with HAS_LIGHT_TREE; the photon pass emits by
  // the table's power all the same).
  LightTree tree;
  if (settings.light_sampler != LightSampler::Power)
    tree = build_sampling_tree(table.lights, table.power, settings.light_sampler);
  lights_ = DeviceLights(ctx, table, tree);
  light_count_ = lights_.count();
  // A wave covers the whole image; settings.chunk_pixels bounds the slots.
  chunk_pixels_ = size_t(settings.width) * size_t(settings.height);
  slots_ = std::max<size_t>(1, std::min({settings.chunk_pixels, kPathSlots, chunk_pixels_ * Film::kMostWavePasses}));
  environment_light_ = table.environment;
  for (DeviceQueue& q : rays_) q = DeviceQueue(ctx, path_record_layout(), slots_);
  shadow_ = DeviceQueue(ctx, shadow_record_layout(), slots_);
  hits_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, slots_ * sizeof(Hit));
  loop_ = std::make_unique<WaveLoop>(launcher, std::vector<int>{1, int(WAVE_PROGRESS_VALUES)});
  if (settings.kernel_shape == KernelShape::Paths) paths_ = StageKernel(program, "trace_paths");
  if (settings.check_numerics) {
    numerics_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, NUMERICS_COUNTERS * sizeof(cl_ulong));
    // Zeroed here too: a resumed render (render_state.h) starts past pass 0.
    launcher.runtime().fill(numerics_, cl_ulong(0), 0, NUMERICS_COUNTERS * sizeof(cl_ulong));
  }
  if (settings.caustics) {
    // As phong's: the program declares the photon map's parameters.
    if (light_count_ == 0) throw Error("path: the photon pass needs a light that emits photons");
    photons_ = std::make_unique<PhotonPass>(launcher, scene, program, lights_, settings);
  }
}

bool PathIntegrator::trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int passes,
                                 RenderStats* stats) {
  const Scene& scene = scene_.scene();
  // An uneven film lists the wave's pixels (those this process traces:
  // pass_driver.h's WaveShare) with their samples; otherwise every pixel
  // of the chunk takes `passes`.
  const bool listed = !film.uniform();
  if (listed && (first_pixel != film.wave_traced_pixels().first ||
                 first_pixel + pixel_count != film.wave_traced_pixels().second))
    throw Error("path: an adaptive wave is traced over the pixels it lists, in one chunk");
  const size_t samples = listed ? size_t(film.wave_traced_samples()) : pixel_count * size_t(passes);
  if (samples == 0) return true;
  PathParams params{};
  params.background = to_float4(scene.background);
  params.light_count = cl_uint(light_count_);
  params.max_depth = cl_uint(std::max(0, scene.nbounces));
  params.ray_capacity = cl_uint(slots_);
  params.first_pass = cl_uint(film.wave_first_pass());
  params.seed = settings_.seed;
  params.strategy = settings_.path_strategy;
  params.rr_depth = kRouletteDepth;
  params.sampler = settings_.sampler;
  params.wave_pixels = cl_uint(pixel_count);
  params.wave_samples = cl_uint(samples);
  params.wave_entries = film.wave_entries();
  params.environment_light = environment_light_;
  const CameraGPU camera = chunk_camera(first_pixel, pixel_count);
  if (settings_.kernel_shape == KernelShape::Paths) return trace_paths(film, params, camera, samples, stats);

  KernelArgs generate(generate_);
  generate.arg("camera", camera)
      .arg("params", params)
      .queue("out", rays_[0], loop_->traced_count(0))
      .arg("next_count", loop_->pushed_count(0))
      .arg("wave_progress", loop_->extra(kWaveProgress));
  film.bind_wave_allocation(generate).finish();
  const size_t started = std::min(samples, slots_);
  launcher_.launch(generate_, started, stats);
  if (stats) stats->camera_rays += samples;

  const bool shadows = light_count_ > 0 && settings_.path_strategy != PATH_STRATEGY_BSDF;
  auto enqueue = [&](uint32_t j, size_t bound) {
    const DeviceQueue& current = rays_[j % 2];
    const DeviceQueue& next = rays_[(j + 1) % 2];
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", current, loop_->traced_count(j)).arg("hits", hits_).finish();
    launcher_.launch(intersect_, bound, stats);

    KernelArgs shade(shade_);
    bind_path_stage_data(shade, film, params);
    shade.queue("in", current, loop_->traced_count(j))
        .arg("hits", hits_)
        .queue("next", next, loop_->pushed_count(j))
        .arg("cleared_count", loop_->cleared_count(j))
        .queue("shadow", shadow_, loop_->traced_count(j));
    bind_wave_sampling(shade, film, camera);
    shade.finish();
    launcher_.launch(shade_, bound, stats);

    if (shadows) {
      KernelArgs shadow(shadow_stage_);
      film.bind(scene_.bind_geometry(shadow).queue("shadow", shadow_, loop_->traced_count(j)))
          .arg("traced", loop_->extra(kShadowRays))
          .finish();
      launcher_.launch(shadow_stage_, bound, stats);
    }
  };
  // Until the wave's samples have all started, ended paths refill their
  // slots; after, the counts only fall.
  auto decide = [&](const WaveLoop::Counters& after, uint32_t seen) -> size_t {
    if (after.extra(kWaveProgress, WAVE_SAMPLES_STARTED) < samples) return slots_;
    const cl_uint remaining = after.queue_count(seen + 1);
    return remaining == 0 ? WaveLoop::kStop : remaining;
  };
  loop_->run(started, ~0u, enqueue, decide, stats);  // never overflows: a path pushes one record at most
  count_wave_rays(loop_->last().extra(kWaveProgress, WAVE_CLOSEST_RAYS), loop_->last().extra(kShadowRays), samples,
                  stats);
  return true;
}

void PathIntegrator::count_wave_rays(cl_uint closest_rays, cl_uint shadow_rays, size_t samples, RenderStats* stats) {
  // The wave's rays: the counters run over the render (modulo 2^32).
  const cl_uint closest = closest_rays - closest_rays_seen_, shadow = shadow_rays - shadow_rays_seen_;
  closest_rays_seen_ = closest_rays;
  shadow_rays_seen_ = shadow_rays;
  pass_rays_ += uint64_t(closest) + shadow;
  if (stats) {
    stats->secondary_rays += closest - std::min<uint64_t>(closest, samples);
    stats->shadow_rays += shadow;
  }
}

void PathIntegrator::bind_path_stage_data(KernelArgs& args, Film& film, const PathParams& params) {
  scene_.bind_scene_buffers(args, lights_).arg("params", params);
  film.bind(args);
  if (photons_)
    photons_->bind_photon_map(
        photons_->bind_visible_points(args).arg("record_visible_points", cl_uint(photon_pass_now_ ? 1 : 0)));
  if (numerics_()) args.arg("numerics", numerics_);
  if (settings_.aux_passes) film.bind_aux(args);
}

void PathIntegrator::bind_wave_sampling(KernelArgs& args, Film& film, const CameraGPU& camera) {
  args.arg("camera", camera).arg("wave_progress", loop_->extra(kWaveProgress));
  film.bind_pixel_rays(film.bind_wave_allocation(args))
      .arg("count_pixel_rays", cl_uint(settings_.adaptive && settings_.adaptive_options.weigh_cost ? 1 : 0));
}

bool PathIntegrator::trace_paths(Film& film, const PathParams& params, const CameraGPU& camera, size_t samples,
                                 RenderStats* stats) {
  // One work-item per thread the device runs at once, a work-group each:
  // the work-items take samples until the wave's are all started.
  const size_t workers =
      std::max<size_t>(1, launcher_.runtime().device_info().compute_units) * launcher_.local_size();
  launcher_.runtime().fill(loop_->extra(kWaveProgress), cl_uint(0), WAVE_SAMPLES_STARTED * sizeof(cl_uint),
                           sizeof(cl_uint));
  KernelArgs paths(paths_);
  bind_path_stage_data(paths, film, params);
  paths.arg("traced", loop_->extra(kShadowRays));
  bind_wave_sampling(paths, film, camera);
  paths.finish();
  launcher_.launch(paths_, workers, stats);
  if (stats) stats->camera_rays += samples;
  cl_uint progress[WAVE_PROGRESS_VALUES], shadow_rays = 0;
  launcher_.runtime().queue().enqueueReadBuffer(loop_->extra(kWaveProgress), CL_FALSE, 0, sizeof progress, progress);
  launcher_.runtime().queue().enqueueReadBuffer(loop_->extra(kShadowRays), CL_TRUE, 0, sizeof shadow_rays,
                                                &shadow_rays);
  if (stats) ++stats->blocking_transfers;
  count_wave_rays(progress[WAVE_CLOSEST_RAYS], shadow_rays, samples, stats);
  return true;
}

// After a photon pass gathered (film.passes() is its 0-based index, not yet
// accumulated). Work: a camera pass costs its rays plus the inline gathers
// at later receivers (every pass, with the latest map); a photon pass adds
// its photons' rays and storage and the visible points' gathers, spread
// over interval_ passes. After the first photon pass, interval_ becomes the
// fewest passes per photon map that keep the photon work's share at most
// kMostPhotonShare; off when no interval up to kLongestInterval does, or
// when the inline gathers alone exceed it. After the second, off when the
// caustic carries less than kLeastCausticShare of the image's light. What
// was gathered stays in the image (photon_pass.h), and from the next pass
// on the shade stage counts every path itself.
void PathIntegrator::decide_photon_pass(const Film& film) {
  const uint32_t maps = photons_->photon_passes();
  const int done = film.passes() + 1;
  const PhotonGatherStats& g = photons_->last_pass_gathers();  // summed over the processes already
  // Shared by pixels: this process's rays are its window's and its share
  // of the photons'; the decisions weigh the whole image's.
  std::vector<uint64_t> rays = {pass_rays_, photons_->last_pass_photon_rays()};
  if (share_) share_->sum_to_all(rays);
  const double camera_work = double(rays[0]);
  // the inline gathers of one pass (the counters hold passes_counted_ of them)
  const double inline_work = (kLaterGatherWork * double(g.gathers_later) + kVisitWork * double(g.visits_later)) /
                             double(std::max(1u, passes_counted_));
  const double map_work = kPhotonRayWork * double(rays[1]) +
                          kStoredPhotonWork * double(photons_->last_pass_stored()) +
                          kVisiblePointGatherWork * double(g.gathers_d1) + kVisitWork * double(g.visits_d1);
  char line[400];
  auto say = [&] { decision_ += std::string(decision_.empty() ? "" : "\n") + line; };
  if (maps == 1) {
    // (inline + map / m) / (camera + inline + map / m) <= s  <=>  map / m <= (s camera - (1 - s) inline) / (1 - s)
    const double s = kMostPhotonShare;
    const double room = (s * camera_work - (1.0 - s) * inline_work) / (1.0 - s);
    const double m = room > 0.0 ? std::ceil(map_work / room) : INFINITY;
    if (!(m <= kLongestInterval)) {
      photons_->turn_off(film.spp_after_wave());
      std::snprintf(line, sizeof line,
                    "caustics auto: off after pass %d: a photon map costs %.3g ray-equivalents and the inline "
                    "gathers %.3g a pass, against %.3g for the camera paths: no map interval up to %d passes keeps "
                    "them within %.0f%% of the work",
                    done, map_work, inline_work, camera_work, kLongestInterval, 100.0 * s);
      say();
      return;
    }
    interval_ = least_interval_ = uint32_t(std::max(1.0, m));
    const double share = (inline_work + map_work / interval_) / (camera_work + inline_work + map_work / interval_);
    std::snprintf(line, sizeof line,
                  "caustics auto: a photon map (%u photons) every %u pass%s after pass %d: a map costs %.3g "
                  "ray-equivalents, the inline gathers %.3g and the camera paths %.3g a pass, so the photon work is "
                  "%.0f%% of the total (at most %.0f%%)",
                  photons_->photons_per_pass(), interval_, interval_ == 1 ? "" : "es", done, map_work, inline_work,
                  camera_work, 100.0 * share, 100.0 * s);
    say();
    return;
  }
  if (maps == 2) {
    // The accumulated passes (this one is not yet) with the caustic image
    // (shared: every window's statistics gathered, the films' sums summed;
    // the sums below then run over the pixels in order, as in one process).
    photons_->gather_pixels_to_all();
    const ImageF image = share_ ? film.summed_means(*share_, false).mean : film.mean();
    double total = 0.0;
    for (float v : image.rgb) total += v;
    const double caustic = photons_->caustic_total(film.spp_after_wave());
    const double light_share = total > 0.0 ? caustic / total : 0.0;
    if (light_share < kLeastCausticShare) {
      photons_->turn_off(film.spp_after_wave());
      std::snprintf(line, sizeof line,
                    "caustics auto: off after pass %d: the photon map carries %.2g of the image's light (below %.2g)",
                    done, light_share, kLeastCausticShare);
      say();
      return;
    }
    std::snprintf(line, sizeof line,
                  "caustics auto: kept after pass %d: the photon map carries %.2g of the image's light", done,
                  light_share);
    say();
  }
  if (balanced_ || film.passes() < kBalanceAfterPasses || !film.has_half_buffer()) return;
  // Balance the two errors (both estimated by the render itself): after W
  // work with a map every m passes, E(m) = (C + P / m)(a + b m) / W, where
  // a = E_passes x passes and b = E_map x maps (each error ~ 1 / its
  // count), C a pass's work and P a map's; the best m is sqrt(P a / (C b)),
  // at least the interval the work share allows and at most
  // kLongestInterval.
  balanced_ = true;
  // Shared by pixels: every window's statistics and images, gathered (the
  // photon map's bias term reads each pixel's neighbours).
  photons_->gather_pixels_to_all();
  const Film::Means both = share_ ? film.summed_means(*share_, true) : Film::Means{film.mean(), film.half_mean()};
  const ImageF &mean = both.mean, &half = both.half, map_error = film.separate_variance();
  const double passes_error = estimated_rel_mse(mean, half, film.pixel_spp(), film.half_counts());
  double map_sum = 0.0;
  for (size_t i = 0; i < mean.rgb.size(); ++i)
    map_sum += map_error.rgb[i] / (double(mean.rgb[i]) * mean.rgb[i] + kRelMseEpsilon);
  const double map_rel_mse = mean.rgb.empty() ? 0.0 : map_sum / double(mean.rgb.size());
  const double a = passes_error * film.passes(), b = map_rel_mse * photons_->photon_passes();
  const double best = b > 0.0 ? std::sqrt(map_work * a / ((camera_work + inline_work) * b)) : INFINITY;
  const uint32_t chosen = uint32_t(std::clamp(std::ceil(best), double(least_interval_), double(kLongestInterval)));
  std::snprintf(line, sizeof line,
                "caustics auto: a map every %u pass%s after pass %d: the passes' estimated relMSE %.3g at %d "
                "passes and the photon map's %.3g at %u maps balance at %.1f (at least %u for the work share)",
                chosen, chosen == 1 ? "" : "es", done, passes_error, film.passes(), map_rel_mse,
                photons_->photon_passes(), best, least_interval_);
  say();
  interval_ = chosen;
}

}  // namespace

std::unique_ptr<Integrator> make_path_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings) {
  return std::make_unique<PathIntegrator>(launcher, scene, program, settings);
}

}  // namespace caustica
