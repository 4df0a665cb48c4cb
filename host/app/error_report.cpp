#include "host/app/error_report.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/error.h"
#include "host/write_file.h"

namespace caustica {
namespace {

// A report's columns: the first `count` of kErrorReportColumns (older
// reports have fewer).
struct ColumnLayout {
  const char* line;
  size_t count;
};
constexpr ColumnLayout kLayouts[] = {{kErrorReportColumns, 9},
                                     {kErrorReportColumnsWithoutBound, 8},
                                     {kErrorReportColumnsWithoutDenoised, 6}};

const ColumnLayout* layout_of(const std::string& line) {
  for (const ColumnLayout& layout : kLayouts)
    if (line == layout.line) return &layout;
  return nullptr;
}

// Reader and writer share these rules, so whatever is written reads back.
// Each returns an empty string when the entry is valid, else why not.
std::string check_header_entry(const std::string& key, const std::string& value) {
  if (key.empty()) return "empty key";
  for (char c : key)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      return "key '" + key + "' has a character outside [a-z0-9_]";
  if (value.find_first_of("\r\n") != std::string::npos) return "value of '" + key + "' has a line break";
  return "";
}

std::string check_error_value(const char* column, const std::optional<double>& v) {
  if (v && !(*v >= 0.0)) return std::string(column) + " must be >= 0 (or empty)";
  return "";
}

std::string check_row(const ErrorReportRow& row, const ErrorReportRow* previous) {
  if (!std::isfinite(row.seconds) || row.seconds < 0.0) return "seconds must be a finite number >= 0";
  if (previous && row.seconds < previous->seconds) return "seconds go backwards (previous row has a later time)";
  if (row.spp < 1) return "spp must be an integer >= 1";
  for (const auto& [name, v] :
       {std::pair{"est_relmse", &row.est_relmse}, std::pair{"mse", &row.mse}, std::pair{"relmse", &row.relmse},
        std::pair{"mae", &row.mae}, std::pair{"denoised_est_relmse", &row.denoised_est_relmse},
        std::pair{"denoised_relmse", &row.denoised_relmse}, std::pair{"est_relmse_bound", &row.est_relmse_bound}})
    if (std::string why = check_error_value(name, *v); !why.empty()) return why;
  return "";
}

// Shortest text that reads back as the same double ("0.052", not "0.05200000000000000094").
std::string format_number(double v) {
  std::array<char, 64> buf;
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), res.ptr);
}

bool parse_number(const std::string& text, double& out) {
  const char* end = text.data() + text.size();
  const auto res = std::from_chars(text.data(), end, out);
  return res.ec == std::errc() && res.ptr == end && !std::isnan(out);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(int line, const std::string& why) const {
    throw Error("error report '" + path_ + "', line " + std::to_string(line) + ": " + why);
  }

  std::optional<double> error_value(int line, const char* column, const std::string& text) const {
    if (text.empty()) return std::nullopt;
    double v = 0.0;
    if (!parse_number(text, v)) fail(line, std::string(column) + " '" + text + "' is not a number");
    return v;
  }

  ErrorReportRow row(int line, const std::string& text, const ColumnLayout& layout) const {
    const std::vector<std::string> f = split_fields(text);
    if (f.size() != layout.count)
      fail(line, "expected " + std::to_string(layout.count) + " comma-separated fields (" + layout.line +
                     "), found " + std::to_string(f.size()));
    ErrorReportRow r;
    if (!parse_number(f[0], r.seconds)) fail(line, "seconds '" + f[0] + "' is not a number");
    const char* spp_end = f[1].data() + f[1].size();
    const auto spp = std::from_chars(f[1].data(), spp_end, r.spp);
    if (spp.ec != std::errc() || spp.ptr != spp_end) fail(line, "spp '" + f[1] + "' is not an integer");
    r.est_relmse = error_value(line, "est_relmse", f[2]);
    r.mse = error_value(line, "mse", f[3]);
    r.relmse = error_value(line, "relmse", f[4]);
    r.mae = error_value(line, "mae", f[5]);
    if (layout.count > 6) {
      r.denoised_est_relmse = error_value(line, "denoised_est_relmse", f[6]);
      r.denoised_relmse = error_value(line, "denoised_relmse", f[7]);
    }
    if (layout.count > 8) r.est_relmse_bound = error_value(line, "est_relmse_bound", f[8]);
    return r;
  }

 private:
  std::string path_;
};

}  // namespace

const std::string* ErrorReport::find(const std::string& key) const {
  for (const auto& [k, v] : header)
    if (k == key) return &v;
  return nullptr;
}

ErrorReport read_error_report(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read error report '" + path + "': " + std::strerror(errno));
  const Reader reader(path);
  ErrorReport report;
  enum class Part { Marker, Header, Rows } part = Part::Marker;
  const ColumnLayout* layout = &kLayouts[0];
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows: same content
    if (part == Part::Marker) {
      if (line != kErrorReportMarker)
        reader.fail(number, "expected '" + std::string(kErrorReportMarker) + "' (not a caustica error report)");
      part = Part::Header;
    } else if (part == Part::Header && layout_of(line)) {
      part = Part::Rows;
      layout = layout_of(line);
    } else if (part == Part::Header) {
      const size_t colon = line.find(": ");
      if (line.rfind("# ", 0) != 0 || colon == std::string::npos)
        reader.fail(number, "expected a '# key: value' line or the column line '" + std::string(kErrorReportColumns) +
                                "', found '" + line + "'");
      std::string key = line.substr(2, colon - 2), value = line.substr(colon + 2);
      if (std::string why = check_header_entry(key, value); !why.empty()) reader.fail(number, why);
      if (report.find(key)) reader.fail(number, "key '" + key + "' appears twice");
      report.header.emplace_back(std::move(key), std::move(value));
    } else {
      if (line.empty()) reader.fail(number, "blank line among the rows");
      if (line[0] == '#') reader.fail(number, "comment after the column line (header lines come first)");
      ErrorReportRow row = reader.row(number, line, *layout);
      if (std::string why = check_row(row, report.rows.empty() ? nullptr : &report.rows.back()); !why.empty())
        reader.fail(number, why);
      report.rows.push_back(row);
    }
  }
  if (in.bad()) throw Error("cannot read error report '" + path + "': read failed");
  if (part != Part::Rows)
    reader.fail(number + 1, "file ends before the column line '" + std::string(kErrorReportColumns) + "'");
  return report;
}

void write_error_report(const std::string& path, const ErrorReport& report) {
  std::ostringstream out;
  out << kErrorReportMarker << "\n";
  for (const auto& [key, value] : report.header) {
    if (std::string why = check_header_entry(key, value); !why.empty())
      throw Error("cannot write error report '" + path + "': header " + why);
    out << "# " << key << ": " << value << "\n";
  }
  out << kErrorReportColumns << "\n";
  auto field = [](const std::optional<double>& v) { return v ? format_number(*v) : std::string(); };
  for (size_t i = 0; i < report.rows.size(); ++i) {
    const ErrorReportRow& r = report.rows[i];
    if (std::string why = check_row(r, i ? &report.rows[i - 1] : nullptr); !why.empty())
      throw Error("cannot write error report '" + path + "': row " + std::to_string(i + 1) + ": " + why);
    out << format_number(r.seconds) << ',' << r.spp << ',' << field(r.est_relmse) << ',' << field(r.mse) << ','
        << field(r.relmse) << ',' << field(r.mae) << ',' << field(r.denoised_est_relmse) << ','
        << field(r.denoised_relmse) << ',' << field(r.est_relmse_bound) << "\n";
  }

  write_output_file(path, out.str(), "error report");
}

}  // namespace caustica
