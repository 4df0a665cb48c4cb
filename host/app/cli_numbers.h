// CLI11 validators for floating-point options. CLI11's own Range and
// PositiveNumber let NaN through (every comparison with NaN is false) and
// PositiveNumber lets infinity through, so `--sun-elevation nan` reached the
// sky model and `--checkpoint-every nan` a timer: these refuse them, with
// the option's name and what was expected.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace caustica {

// A finite number in [lo, hi].
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
          return "expected a finite number within [" + CLI::detail::to_string(lo) + ", " +
                 CLI::detail::to_string(hi) + "], got '" + text + "'";
        return std::string();
      },
      "FINITE in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]");
}

// A finite number > 0 (at most `hi`).
inline CLI::Validator finite_positive(double hi = 1e30) {
  return CLI::Validator(
      [hi](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0) || v > hi)
          return "expected a finite number above 0 (at most " + CLI::detail::to_string(hi) + "), got '" + text + "'";
        return std::string();
      },
      "FINITE > 0");
}

// A file name: given, it may not be empty (`--checkpoint ''` saved nothing
// and `-o ''` fell back to the default name, both without a word).
inline CLI::Validator non_empty_path() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "expected a file name, got ''" : std::string(); },
      "PATH");
}

}  // namespace caustica
