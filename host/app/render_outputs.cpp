// What `caustica render` writes: the image and the film's passes, the
// --spp-map heatmap and the --checkpoint state, while rendering and at the
// end; progress on stderr while rendering, and after it the statistics,
// warnings and the list of what was written.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "host/app/render_stages.h"
#include "host/app/spp_heatmap.h"

namespace caustica {
namespace {

std::string format_error(double e) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", e);
  return b;
}

std::string format_seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f s", s);
  return b;
}

}  // namespace

ProgressReporter::ProgressReporter(bool enabled) : enabled_(enabled), tty_(isatty(2)) {}

void ProgressReporter::update(const PassProgress& p) {
  if (!enabled_) return;
  const double s = seconds();
  const double samples = double(p.pixels_total) * p.pass + double(p.pixels_done);  // pixel samples done
  // This run's: a resumed render's rate and time left leave out the state's.
  const double run_samples = samples - double(p.pixels_total) * p.first_pass;
  const bool open_ended = p.passes == std::numeric_limits<int>::max();
  const double total = double(p.pixels_total) * p.passes;
  const uint64_t rays = p.stats ? p.stats->rays() : 0;
  if (s < 1.0 || (!tty_ && s - last_ < 1.0 && samples < total)) return;
  last_ = s;
  // Time left: to the sample target at the current rate, or to the time
  // limit, or to the target error as projected, whichever comes first.
  double left = run_samples > 0 && !open_ended ? s * (total - samples) / run_samples : 1e300;
  if (p.time_limit_s > 0.0) left = std::min(left, std::max(0.0, p.time_limit_s - p.seconds));
  std::optional<double> to_target = monitor_ ? monitor_->seconds_to_target(p.seconds) : std::nullopt;
  if (to_target) left = std::min(left, *to_target);
  char target[32];
  if (open_ended) std::snprintf(target, sizeof target, "%s", "-");
  else std::snprintf(target, sizeof target, "%d", p.passes);
  std::string error;
  if (monitor_ && monitor_->estimate()) {
    error = ", relMSE ~" + format_error(*monitor_->estimate());
    if (monitor_->bound()) error += " (<= " + format_error(*monitor_->bound()) + " at 90%)";
    if (to_target) error += " (target in " + format_seconds(*to_target) + ")";
  }
  std::fprintf(stderr, "%s[caustica] %.2f/%s spp, %.3g samples/s, %.2f Mrays/s%s, %.1f s elapsed, %s left%s",
               tty_ ? "\r" : "", samples / double(p.pixels_total), target, run_samples / s, rays / s * 1e-6,
               error.c_str(), s, left < 1e299 ? format_seconds(left).c_str() : "?", tty_ ? "\x1b[K" : "\n");
  printed_ = true;
}

void ProgressReporter::finish() {
  if (printed_ && tty_) std::fprintf(stderr, "\n");
}

RenderOutputs::RenderOutputs(const RenderArgs& a, const RenderPlan& plan)
    : args_(a), session_(*plan.session), identity_(plan.identity) {
  film_options_.output = a.output;
  film_options_.aov_dir = a.aov_dir;
  film_options_.display = plan.display;
  film_options_.denoiser = plan.denoiser.get();
  film_options_.verbose = a.verbose;
  film_options_.guides = plan.guides;
}

// The image, with its per-pixel sample counts where they can go: an .exr
// output's "spp" channel, and the --spp-map heatmap.
void RenderOutputs::write_images(const ImageF& image, const Film& film) {
  if (session_.mode == RenderMode::Path)
    write_film_outputs(film_options_, film);
  else
    write_image(args_.output, image, film_options_.display);
  if (!args_.spp_map.empty()) {
    char title[160];
    std::snprintf(title, sizeof title, "%s: samples per pixel (mean %d, %s)",
                  std::filesystem::path(session_.scene.source_path).filename().string().c_str(), film.passes(),
                  session_.settings.adaptive ? "adaptive" : "uniform");
    write_spp_heatmap(args_.spp_map, film.width(), film.height(), film.pixel_spp(), title);
  }
}

void RenderOutputs::write_checkpoint(const Renderer& renderer) {
  if (renderer.film().passes() == checkpoint_passes_) return;  // the same state again
  RenderState state = renderer.state();
  state.identity = identity_;
  write_render_state(args_.checkpoint, state);
  checkpoint_passes_ = state.film.passes;
  if (args_.verbose)
    std::fprintf(stderr, "[caustica] checkpoint %s at %d spp\n", args_.checkpoint.c_str(), state.film.passes);
}

void RenderOutputs::on_pass(const Renderer& renderer, const Film& film, double seconds) {
  if (args_.write_every_s > 0.0 && seconds - last_write_ >= args_.write_every_s) {
    last_write_ = seconds;
    write_images(film.mean(), film);
  }
  if (!args_.checkpoint.empty() &&
      seconds - last_checkpoint_ >= args_.checkpoint_every_s.value_or(kDefaultCheckpointSeconds)) {
    last_checkpoint_ = seconds;
    write_checkpoint(renderer);
  }
}

// The report's header: what was rendered, where, and what it cost before
// the first sample (the rows' seconds start at the first sample).
std::vector<std::pair<std::string, std::string>> report_header(const Session& session, const RenderArgs& a,
                                                               int resumed_passes) {
  char buf[128];
  std::vector<std::pair<std::string, std::string>> h;
  h.emplace_back("scene", session.scene.source_path);
  std::snprintf(buf, sizeof buf, "%s %dx%d %s seed %u%s", render_mode_name(session.mode), session.settings.width,
                session.settings.height,
                session.settings.sampler == SAMPLER_INDEPENDENT ? "independent" : "sobol", session.settings.seed,
                session.mode != RenderMode::Path ? "" : session.settings.adaptive ? " adaptive" : " uniform");
  h.emplace_back("mode", buf);
  h.emplace_back("device", session.runtime->device_info().name + " (" +
                               session.runtime->device_info().platform_name + ")");
  std::snprintf(buf, sizeof buf, "%.3f (%s)", session.program.build_ms / 1e3, session.program.cache_state());
  h.emplace_back("kernel_build_s", buf);
  std::snprintf(buf, sizeof buf, "%.3f", session.bvh.build_ms / 1e3);
  h.emplace_back("bvh_build_s", buf);
  if (!a.reference.empty()) h.emplace_back("reference", a.reference);
  if (!a.resume.empty()) h.emplace_back("resumed_from", a.resume + " at " + std::to_string(resumed_passes) + " spp");
  return h;
}

namespace {

// --check-numerics: what the film dropped, and per scattering event the
// BSDF samples' mean weight (largest channel; a mean above 1 means the
// scene's materials or the sampling gain energy) and how many exceeded 1.
void print_numerics_report(const RenderStats& stats, RenderMode mode) {
  std::fprintf(stderr, "[caustica] numerics: %llu NaN/Inf and %llu negative contributions dropped, %llu clamped\n",
               (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
               (unsigned long long)stats.film.clamped);
  if (mode != RenderMode::Path || stats.numerics.size() != NUMERICS_COUNTERS) {
    std::fprintf(stderr, "[caustica] numerics: per-bounce BSDF weights are counted in path mode only\n");
    return;
  }
  std::fprintf(stderr, "[caustica] numerics: %llu non-finite BSDF weights\n",
               (unsigned long long)stats.numerics[NUMERICS_NONFINITE]);
  bool gain = false;
  for (uint32_t d = 0; d < NUMERICS_DEPTHS; ++d) {
    const uint64_t n = stats.numerics[3 * d], above = stats.numerics[3 * d + 2];
    if (n == 0) continue;
    const double mean = double(stats.numerics[3 * d + 1]) / NUMERICS_WEIGHT_SCALE / double(n);
    gain = gain || mean > 1.001;
    std::fprintf(stderr, "[caustica] numerics: bounce %u%s: %llu BSDF samples, mean weight %.4f, %.3f%% above 1%s\n",
                 d + 1, d + 1 == NUMERICS_DEPTHS ? "+" : "", (unsigned long long)n, mean, 100.0 * double(above) / n,
                 mean > 1.001 ? "  <- energy gain" : "");
  }
  if (gain)
    std::fprintf(stderr, "[caustica] numerics: a mean weight above 1 gains energy at that bounce: check material "
                         "colours above 1 or the BSDF's sampling\n");
}

// -v: what the render traced, moved and dropped, and what the photon pass
// cost and decided.
void print_render_stats(const RenderStats& stats, const ImageF& image) {
  std::fprintf(stderr,
               "[caustica] render: %.1f ms, %dx%d, %llu camera + %llu secondary + %llu shadow + %llu photon rays "
               "(%.2f Mrays/s)%s\n",
               stats.render_ms, image.width, image.height, (unsigned long long)stats.camera_rays,
               (unsigned long long)stats.secondary_rays, (unsigned long long)stats.shadow_rays,
               (unsigned long long)stats.photon_rays, stats.rays() / (stats.render_ms * 1e3),
               stats.chunk_retries ? " (queue overflow: chunks split)" : "");
  std::fprintf(stderr,
               "[caustica] host traffic: %llu kernel launches, %llu blocking transfers, %llu count reads "
               "(non-blocking)\n",
               (unsigned long long)stats.launches, (unsigned long long)stats.blocking_transfers,
               (unsigned long long)stats.count_reads);
  std::fprintf(stderr,
               "[caustica] film: %d passes; dropped %llu NaN/Inf and %llu negative contributions, clamped %llu, "
               "%llu below its resolution\n",
               stats.passes, (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
               (unsigned long long)stats.film.clamped, (unsigned long long)stats.film.underflow);
  if (stats.photon_rays > 0) {
    const PhotonGatherStats& g = stats.photon_gathers;
    auto per = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
    std::fprintf(stderr,
                 "[caustica] photons: %u maps in %.3f s (%.1f%% of the render), %llu rays, %llu stored; gathers at "
                 "visible points %llu (%.1f photons visited each), at later receivers %llu (%.1f each)\n",
                 stats.photon_maps, stats.photon_seconds, 100.0 * stats.photon_seconds / (stats.render_ms * 1e-3),
                 (unsigned long long)stats.photon_rays, (unsigned long long)stats.photons_stored,
                 (unsigned long long)g.gathers_d1, per(g.visits_d1, g.gathers_d1),
                 (unsigned long long)g.gathers_later, per(g.visits_later, g.gathers_later));
  }
  if (!stats.caustics_decision.empty()) {
    std::string d = stats.caustics_decision;
    for (size_t at = 0; (at = d.find('\n', at)) != std::string::npos; at += 12) d.replace(at, 1, "\n[caustica] ");
    std::fprintf(stderr, "[caustica] %s\n", d.c_str());
  }
}

// Dropped, clamped or underflowing contributions are never silent.
void warn_film_changes(const RenderArgs& a, const Session& session, const RenderStats& stats) {
  if (stats.film.changed() > 0 && !a.verbose && !a.quiet)
    std::fprintf(stderr, "[caustica] warning: film dropped %llu NaN/Inf and %llu negative contributions, clamped %llu\n",
                 (unsigned long long)stats.film.nonfinite, (unsigned long long)stats.film.negative,
                 (unsigned long long)stats.film.clamped);
  // Contributions below the film's resolution: each lost less than 2^-45;
  // said when together they could be 0.01% of the image's light.
  if (stats.film.underflow > 0 && !a.quiet) {
    const double share = session.renderer->film().underflow_share(stats.film.underflow);
    if (share > 1e-4)
      std::fprintf(stderr,
                   "[caustica] warning: %llu contributions were below the film's resolution (2^-45 = 2.8e-14) and "
                   "rounded to 0: up to %.3g%% of the image's light; scale the scene's light up\n",
                   (unsigned long long)stats.film.underflow, 100.0 * share);
  }
}

// What was written, at how many samples, and how accurate it is.
void print_written(const RenderArgs& a, const RenderPlan& plan, const RenderStats& stats, const RenderResult& result,
                   const ErrorMonitor& monitor) {
  std::string accuracy;
  if (monitor.estimate()) accuracy += ", estimated relMSE " + format_error(*monitor.estimate());
  if (monitor.bound()) accuracy += " (<= " + format_error(*monitor.bound()) + " at 90%)";
  if (monitor.true_rel_mse()) accuracy += ", relMSE against the reference " + format_error(*monitor.true_rel_mse());
  if (monitor.denoised_estimate()) accuracy += "; denoised: estimated relMSE " + format_error(*monitor.denoised_estimate());
  if (monitor.denoised_true_rel_mse())
    accuracy += std::string(monitor.denoised_estimate() ? "," : "; denoised:") + " relMSE against the reference " +
                format_error(*monitor.denoised_true_rel_mse());
  if (a.target_error > 0.0 && monitor.bound() && *monitor.bound() <= a.target_error)
    accuracy += "; stopped on the bound reaching --target-error " + format_error(a.target_error);
  std::string resumed;
  if (plan.resume) resumed = ", resumed from " + std::to_string(plan.resumed_passes) + " spp in " + a.resume;
  std::fprintf(stderr, "[caustica] %s%s (%dx%d, %d spp%s) in %.2f s%s\n", a.write_output ? "wrote " : "rendered",
               a.write_output ? a.output.c_str() : "", result.image.width, result.image.height,
               result.shown->film().passes(), resumed.c_str(), stats.render_ms / 1e3, accuracy.c_str());
  if (!a.checkpoint.empty())
    std::fprintf(stderr, "[caustica] wrote %s (the render's state at %d spp)\n", a.checkpoint.c_str(),
                 result.shown->film().passes());
  if (!a.report.empty())
    std::fprintf(stderr, "[caustica] wrote %s (%d measurements, %.1f ms measuring = %.2f%% of the render)%s%s\n",
                 a.report.c_str(), monitor.measurements(), monitor.measurement_seconds() * 1e3,
                 100.0 * monitor.measurement_seconds() / std::max(1e-9, stats.render_ms / 1e3),
                 a.plot.empty() ? "" : " and ", a.plot.c_str());
}

}  // namespace

void report_render(const RenderArgs& a, const RenderPlan& plan, const RenderStats& stats, const RenderResult& result,
                   const ErrorMonitor& monitor) {
  if (a.verbose) print_render_stats(stats, result.image);
  if (a.session.check_numerics) print_numerics_report(stats, plan.session->mode);
  warn_film_changes(a, *plan.session, stats);
  if (!a.quiet) print_written(a, plan, stats, result, monitor);
}

}  // namespace caustica
