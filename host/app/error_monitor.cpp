#include "host/app/error_monitor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "host/app/plot.h"
#include "host/denoise/film_denoise.h"
#include "host/image/metrics.h"
#include "host/render/error_estimate.h"
#include "host/render/film.h"

namespace caustica {

ErrorMonitor::ErrorMonitor(ErrorMonitorOptions options) : options_(std::move(options)) {
  report_.header = options_.header;
}

bool ErrorMonitor::on_pass(const Film& film, double seconds) {
  const int passes = film.passes();
  if (options_.sparse_from > 0 && next_power_ < options_.sparse_from) next_power_ = options_.sparse_from;
  const bool geometric = passes >= next_power_;
  const bool target_check = next_target_check_ > 0 && passes >= next_target_check_;
  if (!geometric && !target_check) return true;
  while (next_power_ <= passes) next_power_ = next_power_ > std::numeric_limits<int>::max() / 2 ? passes + 1 : 2 * next_power_;
  measure(film, seconds);
  if (options_.target_error <= 0.0 || !bound_) return true;
  if (*bound_ <= options_.target_error) return false;
  // Error falls as 1 / passes: the pass where the bound is projected to
  // reach the target, at least the next one. The geometric schedule bounds
  // the jump.
  const double projected = std::ceil(passes * (*bound_ / options_.target_error));
  const double furthest = options_.sparse_from > 0 ? 4.0 * passes : double(next_power_);
  next_target_check_ = int(std::clamp(projected, double(passes + 1), std::max(furthest, double(passes + 1))));
  if (options_.sparse_from > 0) next_power_ = std::numeric_limits<int>::max();  // the projection alone
  return true;
}

void ErrorMonitor::finish(const Film& film, double seconds) {
  if (film.passes() > 0 && film.passes() != measured_passes_) measure(film, seconds);
  if (!options_.report_path.empty()) write_report();  // with the last measurement's cost
  if (!options_.plot_path.empty()) {
    if (options_.report_path.empty()) throw Error("--plot needs --report (the plot is drawn from the report)");
    plot_error_reports({options_.report_path}, options_.plot_path);
  }
}

std::optional<double> ErrorMonitor::seconds_to_target(double now) const {
  if (options_.target_error <= 0.0 || !bound_ || measured_passes_ == 0) return std::nullopt;
  if (*bound_ <= options_.target_error) return 0.0;
  const double seconds_per_pass = measured_seconds_ / measured_passes_;
  const double passes_needed = measured_passes_ * (*bound_ / options_.target_error);
  return std::max(0.0, passes_needed * seconds_per_pass - now);
}

void ErrorMonitor::measure(const Film& film, double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  const int passes = film.passes();
  ErrorReportRow row;
  row.seconds = std::max(seconds, report_.rows.empty() ? 0.0 : report_.rows.back().seconds);
  row.spp = passes;
  ImageF mean = film.mean();
  if (film.has_half_buffer() && passes >= 2) {
    // Of the image as written (times the exposure scale), as the truth.
    const Film::SeparateError separate = film.separate_error();
    const RelMseEstimate e = estimate_rel_mse(mean, film.half_mean(), film.pixel_spp(), film.half_counts(),
                                              &separate.variance, &separate.bias2, options_.exposure_scale);
    estimate_ = e.estimate;
    bound_ = e.bound;
    row.est_relmse = estimate_;
    row.est_relmse_bound = bound_;
  }
  if (options_.reference) {
    for (float& v : mean.rgb) v *= options_.exposure_scale;
    row.mse = caustica::mse(mean, *options_.reference);
    row.relmse = rel_mse(mean, *options_.reference);
    row.mae = mean_abs_error(mean, *options_.reference);
    true_rel_mse_ = row.relmse;
  }
  // The denoised image's, only where someone reads it (a report, or a
  // reference to measure against): each costs one to three denoiser runs.
  if (options_.denoiser && (options_.reference || !options_.report_path.empty())) {
    const FilmPasses film_passes = read_film_passes(film, options_.guides);
    const ImageF denoised = denoise_passes(*options_.denoiser, film_passes);
    denoised_estimate_ = estimate_denoised_rel_mse(*options_.denoiser, film, denoised, options_.guides);
    row.denoised_est_relmse = denoised_estimate_;
    if (options_.reference) {
      ImageF scaled = denoised;
      for (float& v : scaled.rgb) v *= options_.exposure_scale;
      denoised_true_rel_mse_ = rel_mse(scaled, *options_.reference);
      row.denoised_relmse = denoised_true_rel_mse_;
    }
  }
  report_.rows.push_back(row);
  measured_passes_ = passes;
  measured_seconds_ = seconds;
  if (!options_.report_path.empty()) write_report();
  measurement_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void ErrorMonitor::write_report() const {
  ErrorReport out = report_;
  char value[64];
  std::snprintf(value, sizeof value, "%.4f (%zu measurements, included in the rows' seconds)", measurement_s_,
                report_.rows.size());
  out.header.emplace_back("measurement_s", value);
  write_error_report(options_.report_path, out);
}

}  // namespace caustica
