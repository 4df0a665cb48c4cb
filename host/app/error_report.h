// Error reports: how a render's error evolved over time, one CSV file per
// render (written by the renderer, read by `caustica plot`). The format, which
// read_error_report accepts exactly and write_error_report produces:
//
//   # caustica error report
//   # scene: scenes/cornell_box.json
//   # mode: path 512x512 sobol seed 0
//   # reference: ref.pfm
//   seconds,spp,est_relmse,mse,relmse,mae,denoised_est_relmse,denoised_relmse,est_relmse_bound
//   0.052,1,,,,,,,
//   0.101,2,0.43,0.012,0.39,0.05,,,2.1
//
// Line 1 is the marker; then any number of "# key: value" lines (keys are
// [a-z0-9_]+ and unique, values one line, kept in file order); then the column
// line; then one row per sample. Columns: wall seconds since the first sample
// (finite, >= 0, non-decreasing), samples per pixel (integer >= 1), the
// render's own relMSE estimate (empty when it cannot estimate, e.g. at 1 spp),
// and true MSE, relMSE, MAE against a reference (empty without one), then,
// for a render with --denoise, the denoised image's estimated relMSE
// (host/denoise/film_denoise.h) and its true relMSE (empty otherwise). Error
// values are numbers >= 0 or "inf" (metrics.h reports NaN pixels as infinite
// error). The last column is the render's upper bound on its relMSE (the
// estimate's 90% bound, host/render/error_estimate.h; empty where there is no
// estimate); reports written before it, with six or eight columns, still
// read. Numbers are written in the shortest form that reads back to the same
// double, so a report round-trips exactly. Every reading error names the file
// and the line.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

struct ErrorReportRow {
  double seconds = 0.0;
  int64_t spp = 0;
  std::optional<double> est_relmse, mse, relmse, mae;
  std::optional<double> denoised_est_relmse, denoised_relmse;  // --denoise
  std::optional<double> est_relmse_bound;  // the estimate's 90% upper bound
};

struct ErrorReport {
  std::vector<std::pair<std::string, std::string>> header;  // "# key: value" lines in order
  std::vector<ErrorReportRow> rows;

  // The value of a header key, or nullptr.
  const std::string* find(const std::string& key) const;
};

constexpr const char* kErrorReportMarker = "# caustica error report";
constexpr const char* kErrorReportColumns =
    "seconds,spp,est_relmse,mse,relmse,mae,denoised_est_relmse,denoised_relmse,est_relmse_bound";
// The column lines of older reports (without the bound; without --denoise's).
constexpr const char* kErrorReportColumnsWithoutBound =
    "seconds,spp,est_relmse,mse,relmse,mae,denoised_est_relmse,denoised_relmse";
constexpr const char* kErrorReportColumnsWithoutDenoised = "seconds,spp,est_relmse,mse,relmse,mae";

ErrorReport read_error_report(const std::string& path);
// Writes to a temporary file beside `path` and renames it into place, so a
// report rewritten during a render is never seen half-written. Throws on a
// report that read_error_report would reject.
void write_error_report(const std::string& path, const ErrorReport& report);

}  // namespace caustica
