// Milliseconds since a steady-clock instant: what -v, the benchmarks and the
// light tree's build report.
#pragma once

#include <chrono>

namespace caustica {

inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace caustica
