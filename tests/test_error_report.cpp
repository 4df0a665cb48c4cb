// Error against run time (issue 12), end to end on the Cornell box:
// - the film's own relMSE estimate on hand-made images equals the formula;
// - true MSE against a long render falls at the Monte Carlo rate (log-log
//   slope of MSE against spp in [-1.15, -0.85]);
// - the estimate stays within a factor of 2 of the true relMSE from 8 spp on;
// - report rows are monotone in time and spp;
// - --target-error stops at the first measurement whose 90% bound is at or
//   below the target, and not far below it;
// - a bad reference (missing, not HDR, wrong size) is an error before any
//   rendering.
// The reference is rendered with another seed, so its own error is
// independent of the renders judged against it (and, at 16x their largest
// spp, adds about 6% to their measured MSE).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "host/app/error_report.h"
#include "host/app/render_command.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/render/error_estimate.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::Contains;

RenderArgs cornell_args(const std::string& output, int spp, uint32_t seed) {
  RenderArgs a;
  a.session.scene_path = test::source_dir() + "/scenes/cornell_box.json";
  a.session.device = test::device_spec();
  a.session.width = 48;
  a.session.spp = spp;
  a.session.seed = seed;
  a.output = output;
  a.quiet = true;
  return a;
}

// One reference and one 128-spp report (adaptive, the default), and four
// uniform ones with independent samples, shared by the tests below.
// (Files live in the first test's temp_dir(), removed when it ends: what
// later tests need is kept in memory.)
struct CornellReport {
  ImageF reference;
  ErrorReport sobol;
  std::vector<ErrorReport> independent;  // seeds 0..3
  CornellReport() {
    const std::string dir = test::temp_dir(), reference_path = dir + "/reference.pfm";
    RenderArgs ref = cornell_args(reference_path, 2048, 1);
    ref.no_error_estimate = true;
    run_render(ref);
    reference = read_pfm(reference_path);
    for (int k = 0; k < 5; ++k) {
      RenderArgs a = cornell_args(dir + "/image.pfm", 128, uint32_t(std::max(0, k - 1)));
      a.reference = reference_path;
      a.report = dir + "/report.csv";
      a.session.independent_samples = k > 0;
      // The Monte Carlo rate below is uniform sampling's; the Sobol-Burley
      // report renders with the default, adaptive sampling.
      a.session.adaptive = k == 0;
      run_render(a);
      if (k == 0) sobol = read_error_report(a.report);
      else independent.push_back(read_error_report(a.report));
    }
  }
};

// Least-squares slope of log(mean MSE over the reports) against log(spp),
// from 4 spp on. One render's MSE is heavy-tailed (a few pixels at the
// light's edge dominate it), so the statement E[MSE] ~ 1/spp is checked on
// the mean of several seeds.
double fitted_slope(const std::vector<ErrorReport>& reports) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t i = 0; i < reports[0].rows.size(); ++i) {
    if (reports[0].rows[i].spp < 4) continue;
    double mse = 0.0;
    for (const ErrorReport& r : reports) mse += *r.rows.at(i).mse / reports.size();
    const double x = std::log(double(reports[0].rows[i].spp)), y = std::log(mse);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// The renders are shared by the checks below, so they run as one test (each
// test is a process of its own under ctest).
const CornellReport* shared_report = nullptr;
const CornellReport& cornell() { return *shared_report; }

std::string error_of(RenderArgs a) {
  try {
    run_render(a);
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(ErrorEstimate, MatchesTheFormulaOnHandMadeImages) {
  // N = 4 passes, half = passes 2 and 3 (n_B = 2, n_A = 2). Per value:
  // (M - B)^2 / (M^2 + 0.01) * n_B / n_A.
  ImageF mean(1, 1), half(1, 1);
  mean.rgb = {1.0f, 0.0f, 0.5f};
  half.rgb = {1.2f, 0.1f, 0.5f};
  const double expected = (0.04 / 1.01 + 0.01 / 0.01 + 0.0) / 3.0;
  EXPECT_NEAR(estimated_rel_mse(mean, half, 4, 2), expected, 1e-6);
  // N = 5, half = pass 4 alone (n_B = 1, n_A = 4): a quarter of that.
  EXPECT_NEAR(estimated_rel_mse(mean, half, 5, 1), expected / 4.0, 1e-6);
  EXPECT_THROW(estimated_rel_mse(mean, half, 1, 1), Error);
}

void check_rows_monotone_and_geometric() {
  const ErrorReport& r = cornell().sobol;
  std::vector<int64_t> spp;
  for (const auto& row : r.rows) spp.push_back(row.spp);
  EXPECT_EQ(spp, (std::vector<int64_t>{1, 2, 4, 8, 16, 32, 64, 128}));
  for (size_t i = 1; i < r.rows.size(); ++i) EXPECT_GE(r.rows[i].seconds, r.rows[i - 1].seconds);
  EXPECT_FALSE(r.rows[0].est_relmse.has_value());  // one pass: nothing to compare
  for (const auto& row : r.rows) EXPECT_TRUE(row.mse && row.relmse && row.mae) << row.spp << " spp";
  for (const char* key : {"scene", "mode", "device", "kernel_build_s", "bvh_build_s", "reference", "measurement_s"})
    EXPECT_NE(r.find(key), nullptr) << key;
  // Adaptive sampling, the default: its rows are at the same mean-spp
  // milestones, and its estimate is what the checks below judge.
  ASSERT_NE(r.find("mode"), nullptr);
  EXPECT_NE(r.find("mode")->find("adaptive"), std::string::npos) << *r.find("mode");
}

// Independent samples: plain Monte Carlo, MSE proportional to 1 / spp.
// Sobol-Burley samples are quasi-Monte Carlo and may converge faster (on
// the Cornell box they do, about spp^-1.5, in the light's and the edges'
// pixels): they must do at least as well.
void check_monte_carlo_rate() {
  const double independent = fitted_slope(cornell().independent), sobol = fitted_slope({cornell().sobol});
  std::printf("[measure] Cornell box 48x48, log-log slope of MSE against spp (4..128): independent %.3f "
              "(mean of 4 seeds), "
              "Sobol-Burley %.3f\n", independent, sobol);
  EXPECT_GE(independent, -1.15);
  EXPECT_LE(independent, -0.85);
  EXPECT_LE(sobol, -0.85);
}

// Past 8 spp (the estimate's denominator is the noisy image itself, so it
// runs low while fireflies dominate), for both samplers.
void check_estimate_within_twice_the_truth() {
  for (const ErrorReport* r : {&cornell().sobol, &cornell().independent[0]})
  for (const auto& row : r->rows) {
    if (row.spp <= 8) continue;
    const double ratio = *row.est_relmse / *row.relmse;
    std::printf("[measure] %s %lld spp: estimated relMSE %.3g, true %.3g, ratio %.2f\n", r->find("mode")->c_str(), (long long)row.spp,
                *row.est_relmse, *row.relmse, ratio);
    EXPECT_GT(ratio, 0.5) << row.spp << " spp";
    EXPECT_LT(ratio, 2.0) << row.spp << " spp";
  }
}

void check_target_error() {
  // A target between the 64- and 128-spp bounds of the shared report: the
  // render stops on the bound (issue 45), not on the point estimate. (At
  // 16 spp the bound is still far above: a few pixels rest on a handful
  // of samples there, and it falls faster than 1 / spp until they don't:
  // 16x from 16 to 32 spp and 7x from 32 to 64 on this 48 x 48 box.)
  const ErrorReport& shared = cornell().sobol;
  const double target = std::sqrt(*shared.rows[6].est_relmse_bound * *shared.rows[7].est_relmse_bound);
  const std::string dir = test::temp_dir();
  RenderArgs a = cornell_args(dir + "/target.pfm", 0, 0);
  a.target_error = target;
  a.report = dir + "/target.csv";
  run_render(a);
  const ErrorReport r = read_error_report(a.report);
  ASSERT_GE(r.rows.size(), 2u);
  const double last = *r.rows.back().est_relmse_bound;
  std::printf("[measure] target %.3g: stopped at %lld spp with a bound of %.3g, estimate %.3g (previous row %lld "
              "spp: bound %.3g)\n",
              target, (long long)r.rows.back().spp, last, *r.rows.back().est_relmse,
              (long long)r.rows[r.rows.size() - 2].spp, *r.rows[r.rows.size() - 2].est_relmse_bound);
  EXPECT_LE(last, target);
  EXPECT_LT(*r.rows.back().est_relmse, last);
  EXPECT_GT(last, 0.5 * target);  // just below: it did not run on to the next power of two and beyond
  for (size_t i = 1; i + 1 < r.rows.size(); ++i) EXPECT_GT(*r.rows[i].est_relmse_bound, target) << "row " << i;
}

void check_bad_reference(const CornellReport& cornell) {
  const std::string dir = test::temp_dir();
  RenderArgs a = cornell_args(dir + "/never.png", 4, 0);
  a.reference = dir + "/missing.pfm";
  EXPECT_TRUE(Contains(error_of(a), {"--reference", "missing.pfm"}));
  a.reference = dir + "/reference.png";
  EXPECT_TRUE(Contains(error_of(a), {"--reference", "reference.png", ".pfm or .exr"}));
  a.reference = dir + "/reference.pfm";
  write_image(a.reference, cornell.reference, DisplaySettings{});
  a.session.width = 64;
  EXPECT_TRUE(Contains(error_of(a), {"--reference", "48x48", "64x64"}));
  EXPECT_FALSE(std::ifstream(dir + "/never.png").good());  // nothing was rendered
}

TEST(ErrorReport, CornellBoxReportsConvergeAndEstimateTheirError) {
  const CornellReport report;
  shared_report = &report;
  {
    SCOPED_TRACE("rows monotone, geometric, complete");
    check_rows_monotone_and_geometric();
  }
  {
    SCOPED_TRACE("Monte Carlo rate");
    check_monte_carlo_rate();
  }
  {
    SCOPED_TRACE("estimate within 2x of the true relMSE");
    check_estimate_within_twice_the_truth();
  }
  {
    SCOPED_TRACE("--target-error");
    check_target_error();
  }
  {
    SCOPED_TRACE("bad references");
    check_bad_reference(report);
  }
  shared_report = nullptr;
}

}  // namespace
}  // namespace caustica
