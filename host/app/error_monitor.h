// Error against run time, measured while a render runs.
//
// Rules: measurements are taken after passes 1, 2, 4, 8, ... (so a log-log
// plot is evenly filled and the cost stays logarithmic in the sample count)
// and after the last pass. Each one reads the film back once (mean, and the
// odd-pass half when the film keeps it) and records, of the image as it
// would be written (linear, times the exposure scale, which is what
// .pfm/.exr outputs and references hold), the film's own relMSE estimate
// and its 90% upper bound (host/render/error_estimate.h) and, given a
// reference, the true MSE, relMSE and MAE.
// With a target error the render stops when the bound, not the point
// estimate, reaches it (a render must not stop on a figure that reads low
// where light is rare, issue 45), and the next measurement is also placed
// where the bound, falling as 1 / passes, is projected to reach the target,
// so the render stops at or just below it rather than at the next power of
// two.
// A sparse monitor (MPI ranks with only a target error: each measurement
// sums the ranks' films) measures first at `sparse_from` passes and then
// only where the target is projected, at most 4x the passes apart.
// The report file is rewritten after every measurement (a stopped render
// keeps its rows); its header carries the build times and the time spent
// measuring, which the rows' wall seconds include.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/app/error_report.h"
#include "host/denoise/denoiser.h"
#include "host/image/image.h"

namespace caustica {

class Film;

struct ErrorMonitorOptions {
  std::string report_path;           // --report: "" none
  std::string plot_path;             // --plot: drawn from the report at the end; "" none
  std::optional<ImageF> reference;   // --reference, already checked against the image size
  double target_error = 0.0;         // --target-error (the estimate's bound); 0: none
  int sparse_from = 0;               // > 0: sparse measurements from this pass count (rules above)
  float exposure_scale = 1.0f;       // what HDR outputs are multiplied by
  std::vector<std::pair<std::string, std::string>> header;  // report header lines (scene, mode, builds)
  // --denoise: each measurement also denoises the image (and, for its
  // estimate, the film's two halves: host/denoise/film_denoise.h).
  const Denoiser* denoiser = nullptr;
  GuideMode guides = GuideMode::Clean;  // as FilmOutputOptions::guides
};

class ErrorMonitor {
 public:
  explicit ErrorMonitor(ErrorMonitorOptions options);

  // After every pass (the film holds film.passes()); `seconds` since the
  // first sample. False: the target error is reached, stop.
  bool on_pass(const Film& film, double seconds);
  // The pass count at which on_pass measures next.
  int next_measurement() const {
    return next_target_check_ > 0 ? std::min(next_power_, next_target_check_) : next_power_;
  }
  // Whether on_pass would measure a film of `passes` passes (a distributed
  // render sums the ranks' films only then).
  bool wants_measurement(int passes) const {
    return passes >= next_power_ || (next_target_check_ > 0 && passes >= next_target_check_);
  }
  // After the last pass: measures it unless just done, writes the report and
  // the plot.
  void finish(const Film& film, double seconds);

  const std::optional<double>& estimate() const { return estimate_; }  // latest estimated relMSE
  const std::optional<double>& bound() const { return bound_; }        // and its 90% upper bound
  const std::optional<double>& true_rel_mse() const { return true_rel_mse_; }
  // --denoise: the latest denoised image's estimated and true relMSE.
  const std::optional<double>& denoised_estimate() const { return denoised_estimate_; }
  const std::optional<double>& denoised_true_rel_mse() const { return denoised_true_rel_mse_; }
  // Seconds from `now` until the bound is projected to reach the target
  // (error proportional to 1 / time); nullopt without a target or an estimate.
  std::optional<double> seconds_to_target(double now) const;
  double measurement_seconds() const { return measurement_s_; }
  int measurements() const { return int(report_.rows.size()); }
  const ErrorReport& report() const { return report_; }

 private:
  void measure(const Film& film, double seconds);
  void write_report() const;

  ErrorMonitorOptions options_;
  ErrorReport report_;
  std::optional<double> estimate_, bound_, true_rel_mse_;
  std::optional<double> denoised_estimate_, denoised_true_rel_mse_;
  int next_power_ = 1;          // the next geometric measurement (passes)
  int next_target_check_ = 0;   // the pass where the target is projected; 0: none
  int measured_passes_ = 0;     // passes at the latest measurement
  double measured_seconds_ = 0.0;
  double measurement_s_ = 0.0;
};

}  // namespace caustica
