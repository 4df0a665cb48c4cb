// `caustica plot`: error against render time from one or more error reports
// (host/app/error_report.h), on log-log axes through gnuplot. Per report, the
// true relMSE (against the reference) is a solid line with points and the
// render's own estimate a dashed line in the same colour, its 90% bound (a
// report's est_relmse_bound) a thin dotted one, each labelled "NAME (true)" /
// "NAME (estimated)" / "NAME (estimate's 90% bound)" with NAME the file's
// stem (its path when two stems coincide). A grey dash-dot line of slope -1 through the median
// point of the first report shows what unbiased Monte Carlo promises (error
// proportional to 1 / time), to judge the curves against. Points a log axis
// cannot show (time or error <= 0, infinite error) are left out.
#pragma once

#include <string>
#include <vector>

namespace caustica {

// Writes out_path (.png or .svg). Throws caustica::Error naming the report
// that cannot be read or has no relMSE value to draw, or the output gnuplot
// could not write.
void plot_error_reports(const std::vector<std::string>& csv_paths, const std::string& out_path);

}  // namespace caustica
