#include "host/app/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "host/app/error_report.h"
#include "host/app/gnuplot.h"
#include "host/error.h"

namespace caustica {
namespace {

// Distinct on white and for the common colour-vision deficiencies (Okabe-Ito).
constexpr const char* kColours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000"};
constexpr int kColourCount = sizeof kColours / sizeof kColours[0];

struct Point {
  double seconds, error;
};

struct Series {
  std::string name;
  std::vector<Point> truth, estimate, bound;
  std::vector<Point> denoised_truth, denoised_estimate;  // --denoise renders
};

std::vector<Point> drawable(const ErrorReport& report, std::optional<double> ErrorReportRow::*column) {
  std::vector<Point> points;
  for (const ErrorReportRow& row : report.rows) {
    const std::optional<double>& v = row.*column;
    if (v && row.seconds > 0.0 && *v > 0.0 && std::isfinite(*v)) points.push_back({row.seconds, *v});
  }
  return points;
}

std::string datablock(const std::string& name, const std::vector<Point>& points) {
  std::string out = name + " << EOD\n";
  char line[64];
  for (const Point& p : points) {
    std::snprintf(line, sizeof line, "%.9g %.9g\n", p.seconds, p.error);
    out += line;
  }
  return out + "EOD\n";
}

}  // namespace

void plot_error_reports(const std::vector<std::string>& csv_paths, const std::string& out_path) {
  if (csv_paths.empty()) throw Error("cannot draw '" + out_path + "': no error reports given");
  std::map<std::string, int> stem_count;
  for (const auto& path : csv_paths) ++stem_count[std::filesystem::path(path).stem().string()];

  std::vector<Series> series;
  double t_min = HUGE_VAL, t_max = 0.0;
  for (const auto& path : csv_paths) {
    const ErrorReport report = read_error_report(path);
    const std::string stem = std::filesystem::path(path).stem().string();
    Series s{stem_count[stem] > 1 ? path : stem, drawable(report, &ErrorReportRow::relmse),
             drawable(report, &ErrorReportRow::est_relmse), drawable(report, &ErrorReportRow::est_relmse_bound),
             drawable(report, &ErrorReportRow::denoised_relmse), drawable(report, &ErrorReportRow::denoised_est_relmse)};
    if (s.truth.empty() && s.estimate.empty())
      throw Error("error report '" + path + "' has no positive relMSE to plot (the estimate needs at least 2 spp; "
                  "the true relMSE needs a reference)");
    for (const auto* points : {&s.truth, &s.estimate, &s.bound, &s.denoised_truth, &s.denoised_estimate})
      for (const Point& p : *points) t_min = std::min(t_min, p.seconds), t_max = std::max(t_max, p.seconds);
    series.push_back(std::move(s));
  }

  // The slope -1 guide passes through the middle point of the first report's
  // main curve, so it starts where that curve is and shows how far it bends away.
  const std::vector<Point>& first = series[0].truth.empty() ? series[0].estimate : series[0].truth;
  const Point median = first[first.size() / 2];
  // A margin of a quarter decade; a single instant still gets an axis a decade wide.
  const double pad = t_max > t_min ? std::pow(10.0, 0.25) : std::sqrt(10.0);

  std::ostringstream gp;
  gp << gnuplot_output(out_path, 800, 560);
  gp << "set logscale xy\n"
        "set xlabel 'render time [s]'\n"
        "set ylabel 'relMSE'\n"
        "set format x '%g'\n"
        "set format y '%g'\n"
        "set grid xtics ytics lc rgb '#d8d8d8' lt 1\n"
        "set key top right box opaque\n";
  char range[96];
  std::snprintf(range, sizeof range, "set xrange [%.9g:%.9g]\n", t_min / pad, t_max * pad);
  gp << range;
  std::vector<std::string> plots;
  for (size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    const std::string colour = "lc rgb '" + std::string(kColours[i % kColourCount]) + "'";
    const std::string block = "$r" + std::to_string(i);
    // The raw image's curves, then the denoised image's: squares, thinner,
    // in the same colour.
    const struct {
      const std::vector<Point>* points;
      const char *suffix, *style, *title;
    } curves[] = {
        {&s.truth, "t", "with linespoints lw 2 pt 7 ps 0.6", " (true)"},
        {&s.estimate, "e", "with lines lw 2 dt 2", " (estimated)"},
        {&s.bound, "b", "with lines lw 1 dt 3", " (estimate's 90% bound)"},
        {&s.denoised_truth, "dt", "with linespoints lw 1.5 pt 5 ps 0.6", " denoised (true)"},
        {&s.denoised_estimate, "de", "with linespoints lw 1.5 dt 3 pt 4 ps 0.6", " denoised (estimated)"},
    };
    for (const auto& c : curves) {
      if (c.points->empty()) continue;
      gp << datablock(block + c.suffix, *c.points);
      plots.push_back(block + c.suffix + " using 1:2 " + c.style + " " + colour + " title " +
                      gnuplot_quote(s.name + c.title) + " noenhanced");
    }
  }
  char guide[160];
  std::snprintf(guide, sizeof guide, "%.9g / x with lines lw 1.5 dt 4 lc rgb '#707070' title 'slope -1 (error ~ 1/time)' noenhanced",
                median.seconds * median.error);
  plots.push_back(guide);
  gp << "plot ";
  for (size_t i = 0; i < plots.size(); ++i) gp << (i ? ", \\\n     " : "") << plots[i];
  gp << "\n";
  run_gnuplot(gp.str(), out_path);
}

}  // namespace caustica
