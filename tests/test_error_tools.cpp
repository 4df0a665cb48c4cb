// The error tools of issue 12: the HDR metrics, `caustica diff` (reading,
// size checks, heatmap), error reports (format, round trip, errors) and
// `caustica plot`. Expected values are worked out by hand in the comments.
// Tests that draw need gnuplot and skip without it; the one that checks the
// message for a missing gnuplot hides it by emptying PATH.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "host/app/diff.h"
#include "host/app/error_report.h"
#include "host/app/gnuplot.h"
#include "host/app/plot.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::Contains;

constexpr double kInf = std::numeric_limits<double>::infinity();

ImageF image(int w, int h, std::vector<float> values) {
  ImageF img(w, h);
  img.rgb = std::move(values);
  return img;
}

const auto error_message = test::error_of;

using test::slurp;

void spit(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

::testing::AssertionResult IsPng(const std::string& path) {
  const std::string bytes = slurp(path);
  const std::string signature = "\x89PNG\r\n\x1a\n";
  if (bytes.size() <= signature.size()) return ::testing::AssertionFailure() << path << " is empty or missing";
  if (bytes.compare(0, signature.size(), signature) != 0)
    return ::testing::AssertionFailure() << path << " does not start with the PNG signature";
  return ::testing::AssertionSuccess();
}

#define REQUIRE_GNUPLOT() \
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed (Debian: gnuplot-nox): skipped"

// ---- metrics ------------------------------------------------------------

// Reference and image, two pixels. Differences 1, 0, 0 | 0, 0.25, -1.
const ImageF kRef = image(2, 1, {1.0f, 0.0f, 2.0f, 0.5f, 0.125f, 4.0f});
const ImageF kImg = image(2, 1, {2.0f, 0.0f, 2.0f, 0.5f, 0.375f, 3.0f});

TEST(ErrorMetrics, HandComputedValues) {
  // MSE (1 + 0.0625 + 1) / 6; MAE (1 + 0.25 + 1) / 6.
  EXPECT_DOUBLE_EQ(mse(kImg, kRef), 2.0625 / 6.0);
  EXPECT_DOUBLE_EQ(mean_abs_error(kImg, kRef), 2.25 / 6.0);
  // relMSE divides by ref^2 + 0.01: the 0.125 pixel's 0.0625 becomes
  // 0.0625 / 0.025625, which without the epsilon would be 4.
  const double rel = (1.0 / 1.01 + 0.0625 / (0.015625 + 0.01) + 1.0 / 16.01) / 6.0;
  EXPECT_NEAR(rel_mse(kImg, kRef), rel, 1e-12);
  EXPECT_NEAR(mean_error(kImg, kRef, ErrorMetric::RelMse), rel, 1e-12);
  EXPECT_DOUBLE_EQ(mean_error(kImg, kRef, ErrorMetric::Mse), mse(kImg, kRef));
  EXPECT_DOUBLE_EQ(mean_error(kImg, kRef, ErrorMetric::Mae), mean_abs_error(kImg, kRef));
  // PSNR's peak is the reference's largest value, 4: 10 log10(16 / MSE).
  EXPECT_DOUBLE_EQ(psnr_peak(kRef), 4.0);
  EXPECT_NEAR(psnr(kImg, kRef), 10.0 * std::log10(16.0 / (2.0625 / 6.0)), 1e-12);
}

TEST(ErrorMetrics, PerPixelErrorIsTheChannelMean) {
  const std::vector<double> e = per_pixel_error(kImg, kRef, ErrorMetric::Mse);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[0], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(e[1], 1.0625 / 3.0);
  const std::vector<double> a = per_pixel_error(kImg, kRef, ErrorMetric::Mae);
  EXPECT_DOUBLE_EQ(a[0], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(a[1], 1.25 / 3.0);
  const std::vector<double> r = per_pixel_error(kImg, kRef, ErrorMetric::RelMse);
  EXPECT_NEAR(r[1], (0.0625 / 0.025625 + 1.0 / 16.01) / 3.0, 1e-12);
}

TEST(ErrorMetrics, PsnrPeakIsOneForAnAllZeroReference) {
  const ImageF ref(1, 1, 0.0f);
  const ImageF a = image(1, 1, {0.5f, 0.0f, 0.0f});
  EXPECT_DOUBLE_EQ(psnr_peak(ref), 1.0);
  // MSE 0.25 / 3: 10 log10(1 / (1/12)) = 10 log10(12).
  EXPECT_NEAR(psnr(a, ref), 10.0 * std::log10(12.0), 1e-12);
}

TEST(ErrorMetrics, IdenticalImagesHaveZeroErrorAndInfinitePsnr) {
  EXPECT_EQ(mse(kRef, kRef), 0.0);
  EXPECT_EQ(rel_mse(kRef, kRef), 0.0);
  EXPECT_EQ(mean_abs_error(kRef, kRef), 0.0);
  EXPECT_EQ(psnr(kRef, kRef), kInf);
}

TEST(ErrorMetrics, NanPixelIsInfiniteError) {
  ImageF a = kImg;
  a.rgb[4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(mse(a, kRef), kInf);
  EXPECT_EQ(rel_mse(a, kRef), kInf);
  EXPECT_EQ(mean_abs_error(a, kRef), kInf);
  EXPECT_EQ(psnr(a, kRef), -kInf);
  const std::vector<double> e = per_pixel_error(a, kRef, ErrorMetric::RelMse);
  EXPECT_TRUE(std::isfinite(e[0]));
  EXPECT_EQ(e[1], kInf);
}

TEST(ErrorMetrics, NamesParseAndUnknownNamesAreListed) {
  for (ErrorMetric m : {ErrorMetric::Mse, ErrorMetric::RelMse, ErrorMetric::Mae})
    EXPECT_EQ(parse_error_metric(error_metric_name(m)), m);
  EXPECT_TRUE(Contains(error_message([] { parse_error_metric("rmse"); }), {"rmse", "relmse", "mse", "mae"}));
  EXPECT_THROW(mean_abs_error(ImageF(2, 1), ImageF(1, 2)), Error);
}

// ---- diff ---------------------------------------------------------------

TEST(Diff, SizeMismatchNamesBothFilesAndSizes) {
  const std::string dir = test::temp_dir();
  write_image(dir + "/wide.pfm", ImageF(4, 2, 0.5f), DisplaySettings{});
  write_image(dir + "/tall.pfm", ImageF(2, 4, 0.5f), DisplaySettings{});
  const std::string msg = error_message([&] { read_diff_pair(dir + "/wide.pfm", dir + "/tall.pfm"); });
  EXPECT_TRUE(Contains(msg, {dir + "/wide.pfm", "4x2", dir + "/tall.pfm", "2x4"}));
}

TEST(Diff, UnreadableFileIsNamed) {
  const std::string dir = test::temp_dir();
  write_image(dir + "/ok.pfm", ImageF(2, 2), DisplaySettings{});
  EXPECT_TRUE(Contains(error_message([&] { read_diff_pair(dir + "/ok.pfm", dir + "/missing.exr"); }),
                       {dir + "/missing.exr"}));
  spit(dir + "/garbage.png", "not a png");
  EXPECT_TRUE(Contains(error_message([&] { read_diff_pair(dir + "/garbage.png", dir + "/ok.pfm"); }),
                       {dir + "/garbage.png"}));
}

TEST(Diff, EightBitAndFloatImagesShareOneScale) {
  const std::string dir = test::temp_dir();
  // Bytes 0, 51, 255 are 0, 0.2, 1 with no gamma decoding.
  Image8 bytes(2, 1);
  bytes.rgb = {0, 51, 255, 255, 51, 0};
  write_image8(dir + "/a.ppm", bytes);
  write_image(dir + "/b.pfm", image(2, 1, {0.0f, 0.2f, 1.0f, 1.0f, 0.2f, 0.0f}), DisplaySettings{});
  const DiffPair pair = read_diff_pair(dir + "/a.ppm", dir + "/b.pfm");
  EXPECT_TRUE(pair.image.eight_bit);
  EXPECT_FALSE(pair.reference.eight_bit);
  for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(pair.image.image.rgb[i], pair.reference.image.rgb[i], 1e-7) << i;
}

using CommandResult = test::CliResult;
CommandResult run_caustica(const std::string& args) { return test::run_cli(args); }

TEST(Diff, CommandPrintsMetricsThenOneJsonLine) {
  const std::string dir = test::temp_dir();
  write_image(dir + "/img.pfm", kImg, DisplaySettings{});
  write_image(dir + "/ref.pfm", kRef, DisplaySettings{});
  const CommandResult r = run_caustica("diff " + dir + "/img.pfm " + dir + "/ref.pfm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, {"MSE ", "relMSE ", "MAE ", "PSNR "}));
  EXPECT_EQ(r.output.find("8-bit images"), std::string::npos) << r.output;
  const size_t last = r.output.rfind('\n', r.output.size() - 2);
  const std::string json = r.output.substr(last + 1);
  EXPECT_EQ(json.rfind("{\"mse\":0.34375,\"relmse\":", 0), 0u) << json;  // 2.0625 / 6 = 0.34375
  EXPECT_TRUE(Contains(json, {"\"mae\":0.375,", "\"psnr\":"}));

  Image8 bytes(2, 1);
  write_image8(dir + "/img.png", bytes);
  const CommandResult eight = run_caustica("diff " + dir + "/img.png " + dir + "/ref.pfm");
  EXPECT_EQ(eight.status, 0) << eight.output;
  EXPECT_TRUE(Contains(eight.output, {"8-bit images are read as byte / 255"}));

  write_image(dir + "/other.pfm", ImageF(3, 3), DisplaySettings{});
  const CommandResult bad = run_caustica("diff " + dir + "/img.pfm " + dir + "/other.pfm");
  EXPECT_EQ(bad.status, 1);
  EXPECT_TRUE(Contains(bad.output, {"caustica: error:", "other.pfm", "3x3", "2x1"}));
}

TEST(Diff, HeatmapIsAPng) {
  REQUIRE_GNUPLOT();
  const std::string dir = test::temp_dir();
  ImageF ref(16, 8, 0.5f), img(16, 8, 0.5f);
  for (int x = 0; x < 16; ++x) img.at(x, 3)[1] = 0.5f + 0.01f * x;  // error grows along one row
  img.at(0, 0)[0] = std::numeric_limits<float>::quiet_NaN();
  write_error_heatmap(img, ref, ErrorMetric::RelMse, dir + "/heat.png", "heat_map title");
  EXPECT_TRUE(IsPng(dir + "/heat.png"));
  write_error_heatmap(ref, ref, ErrorMetric::Mae, dir + "/identical.png");  // no positive error at all
  EXPECT_TRUE(IsPng(dir + "/identical.png"));
}

// ---- error reports ------------------------------------------------------

constexpr const char* kSampleReport =
    "# caustica error report\n"
    "# scene: scenes/cornell_box.json\n"
    "# mode: path 512x512 sobol seed 0\n"
    "# device: pthread-skylake-avx512 (Portable Computing Language)\n"
    "# kernel_build_s: 0.120 (cached)\n"
    "# bvh_build_s: 0.003\n"
    "# reference: ref.pfm\n"
    "seconds,spp,est_relmse,mse,relmse,mae\n"
    "0.052,1,,0.02,0.9,0.1\n"
    "0.101,2,0.43,0.01,0.45,0.07\n"
    "0.2,4,inf,,,\n";

TEST(ErrorReport, ReadsTheDocumentedFormat) {
  const std::string path = test::temp_dir() + "/run.csv";
  spit(path, kSampleReport);
  const ErrorReport r = read_error_report(path);
  ASSERT_EQ(r.header.size(), 6u);
  EXPECT_EQ(r.header[0], (std::pair<std::string, std::string>{"scene", "scenes/cornell_box.json"}));
  ASSERT_NE(r.find("device"), nullptr);
  EXPECT_EQ(*r.find("device"), "pthread-skylake-avx512 (Portable Computing Language)");
  EXPECT_EQ(*r.find("reference"), "ref.pfm");
  EXPECT_EQ(r.find("seed"), nullptr);
  ASSERT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(r.rows[0].seconds, 0.052);
  EXPECT_EQ(r.rows[0].spp, 1);
  EXPECT_FALSE(r.rows[0].est_relmse.has_value());
  EXPECT_EQ(r.rows[0].relmse, 0.9);
  EXPECT_EQ(r.rows[1].est_relmse, 0.43);
  EXPECT_EQ(r.rows[2].est_relmse, kInf);
  EXPECT_FALSE(r.rows[2].mse.has_value());
  EXPECT_FALSE(r.rows[2].mae.has_value());
}

TEST(ErrorReport, WriteThenReadRoundTripsExactly) {
  const std::string path = test::temp_dir() + "/round.csv";
  ErrorReport report;
  report.header = {{"scene", "scenes/a b.json"}, {"mode", "path 64x64 sobol seed 3"}, {"empty", ""}};
  ErrorReportRow first;
  first.seconds = 0.052;
  first.spp = 1;
  ErrorReportRow second;
  second.seconds = 1.0 / 3.0;  // needs all 17 digits
  second.spp = 2;
  second.est_relmse = 0.1;
  second.mse = 1e-9;
  second.relmse = kInf;
  second.mae = 0.0;
  second.est_relmse_bound = 0.25;
  report.rows = {first, second};
  write_error_report(path, report);
  EXPECT_EQ(slurp(path),
            "# caustica error report\n"
            "# scene: scenes/a b.json\n"
            "# mode: path 64x64 sobol seed 3\n"
            "# empty: \n"
            "seconds,spp,est_relmse,mse,relmse,mae,denoised_est_relmse,denoised_relmse,est_relmse_bound\n"
            "0.052,1,,,,,,,\n"
            "0.3333333333333333,2,0.1,1e-09,inf,0,,,0.25\n");
  const ErrorReport back = read_error_report(path);
  EXPECT_EQ(back.header, report.header);
  ASSERT_EQ(back.rows.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.rows[i].seconds, report.rows[i].seconds);
    EXPECT_EQ(back.rows[i].spp, report.rows[i].spp);
    EXPECT_EQ(back.rows[i].est_relmse, report.rows[i].est_relmse);
    EXPECT_EQ(back.rows[i].mse, report.rows[i].mse);
    EXPECT_EQ(back.rows[i].relmse, report.rows[i].relmse);
    EXPECT_EQ(back.rows[i].mae, report.rows[i].mae);
    EXPECT_EQ(back.rows[i].est_relmse_bound, report.rows[i].est_relmse_bound);
  }
}

TEST(ErrorReport, WriterRefusesWhatTheReaderWouldReject) {
  const std::string path = test::temp_dir() + "/bad.csv";
  ErrorReport report;
  report.header = {{"Bad Key", "x"}};
  EXPECT_TRUE(Contains(error_message([&] { write_error_report(path, report); }), {path, "Bad Key"}));
  report.header.clear();
  report.rows = {ErrorReportRow{}};  // spp 0
  EXPECT_TRUE(Contains(error_message([&] { write_error_report(path, report); }), {path, "row 1", "spp"}));
}

TEST(ErrorReport, MalformedFilesNameFileAndLine) {
  const std::string dir = test::temp_dir();
  const std::string head = "# caustica error report\n# scene: s.json\nseconds,spp,est_relmse,mse,relmse,mae\n";
  struct Case {
    std::string text, line, why;
  };
  const std::vector<Case> cases = {
      {"seconds,spp,est_relmse,mse,relmse,mae\n", "line 1", "not a caustica error report"},
      {"# caustica error report\nscene: s.json\n", "line 2", "'# key: value'"},
      {"# caustica error report\n# scene: a\n# scene: b\n", "line 3", "appears twice"},
      {"# caustica error report\n# scene: s.json\n", "line 3", "ends before the column line"},
      {head + "0.1,1,,,\n", "line 4", "expected 6 comma-separated fields"},
      {head + "0.1,1,,,,\n0.2,2,0.5x,,,\n", "line 5", "est_relmse '0.5x' is not a number"},
      {head + "fast,1,,,,\n", "line 4", "seconds 'fast'"},
      {head + "0.1,1.5,,,,\n", "line 4", "spp '1.5' is not an integer"},
      {head + "0.1,0,,,,\n", "line 4", "spp must be"},
      {head + "0.2,1,,,,\n0.1,2,,,,\n", "line 5", "seconds go backwards"},
      {head + "0.1,1,,,-0.5,\n", "line 4", "relmse must be >= 0"},
      {head + "0.1,1,nan,,,\n", "line 4", "est_relmse 'nan'"},
      {head + "0.1,1,,,,\n\n", "line 5", "blank line"},
      {head + "0.1,1,,,,\n# late: x\n", "line 5", "comment after the column line"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = dir + "/case" + std::to_string(i) + ".csv";
    spit(path, cases[i].text);
    EXPECT_TRUE(Contains(error_message([&] { read_error_report(path); }),
                         {"'" + path + "'", cases[i].line + ":", cases[i].why}))
        << "case " << i;
  }
  EXPECT_TRUE(Contains(error_message([&] { read_error_report(dir + "/absent.csv"); }), {dir + "/absent.csv"}));
}

// ---- plot ---------------------------------------------------------------

void write_sample_reports(const std::string& dir) {
  spit(dir + "/with_ref.csv", kSampleReport);
  spit(dir + "/estimate_only.csv",
       "# caustica error report\nseconds,spp,est_relmse,mse,relmse,mae\n"
       "0.05,1,,,,\n0.1,2,0.5,,,\n0.2,4,0.26,,,\n0.4,8,0.12,,,\n");
}

TEST(Plot, TwoReportsMakeAPng) {
  REQUIRE_GNUPLOT();
  const std::string dir = test::temp_dir();
  write_sample_reports(dir);
  plot_error_reports({dir + "/with_ref.csv", dir + "/estimate_only.csv"}, dir + "/plot.png");
  EXPECT_TRUE(IsPng(dir + "/plot.png"));
  plot_error_reports({dir + "/estimate_only.csv"}, dir + "/plot.svg");
  EXPECT_NE(slurp(dir + "/plot.svg").find("<svg"), std::string::npos);
}

TEST(Plot, ReportWithNothingToDrawIsNamed) {
  const std::string dir = test::temp_dir();
  spit(dir + "/one_spp.csv", "# caustica error report\nseconds,spp,est_relmse,mse,relmse,mae\n0.05,1,,,,\n");
  EXPECT_TRUE(Contains(error_message([&] { plot_error_reports({dir + "/one_spp.csv"}, dir + "/p.png"); }),
                       {dir + "/one_spp.csv", "no positive relMSE"}));
  write_sample_reports(dir);
  EXPECT_TRUE(Contains(error_message([&] { plot_error_reports({dir + "/with_ref.csv"}, dir + "/p.jpg"); }),
                       {dir + "/p.jpg", ".png, .svg"}));
}

TEST(Plot, MissingGnuplotSaysWhatToInstall) {
  const std::string dir = test::temp_dir();
  write_sample_reports(dir);
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", dir.c_str(), 1);  // a directory without gnuplot
  const std::string msg = error_message([&] { plot_error_reports({dir + "/with_ref.csv"}, dir + "/p.png"); });
  setenv("PATH", saved.c_str(), 1);
  EXPECT_TRUE(Contains(msg, {dir + "/p.png", "gnuplot-nox"}));
}

}  // namespace
}  // namespace caustica
