#include "host/app/spp_heatmap.h"

#include <algorithm>
#include <cmath>

#include "host/app/gnuplot.h"
#include "host/error.h"

namespace caustica {
namespace {

// 1, 2 or 5 times a power of ten, at least one sample, so about five ticks
// span the range and every label is a whole count.
double tick_step(double range) {
  const double rough = range / 5.0;
  if (rough <= 1.0) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(rough)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * decade >= rough) return m * decade;
  return 10.0 * decade;
}

}  // namespace

void write_spp_heatmap(const std::string& path, int width, int height, const std::vector<uint32_t>& spp,
                       const std::string& title) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width <= 0 || height <= 0) throw Error("cannot draw '" + path + "': the spp map is empty (" + size + ")");
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (spp.size() != pixels)
    throw Error("cannot draw '" + path + "': the spp map holds " + std::to_string(spp.size()) + " counts, a " + size +
                " map needs " + std::to_string(pixels));
  const auto [fewest, most] = std::minmax_element(spp.begin(), spp.end());
  ColourBar bar;
  bar.lo = *fewest;
  bar.hi = *most;
  // gnuplot cannot draw a colour range of zero width.
  if (bar.hi == bar.lo) bar.lo = std::max(0.0, bar.lo - 1.0), bar.hi += 1.0;
  bar.tic_step = tick_step(bar.hi - bar.lo);
  bar.tic_format = "%.0f";
  bar.label = "samples per pixel";
  bar.label_offset = 2.0;
  draw_heatmap(std::vector<float>(spp.begin(), spp.end()), width, height, bar, title, path);
}

}  // namespace caustica
