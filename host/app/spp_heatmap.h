// The per-pixel sample counts of an adaptive render as a heatmap with a
// colour bar, drawn by gnuplot (host/app/gnuplot.h draw_heatmap): viridis on a
// linear scale from the fewest to the most samples any pixel took, whole
// pixels, top row at the top. Lives in host/app/ beside the other figures, so
// host/image/ never depends on the gnuplot helpers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace caustica {

// A PNG (or SVG, by extension) of `spp`: width x height counts, row-major, top
// row first, as ImageF. The colour bar is labelled "samples per pixel" with
// whole-number ticks; a map where every pixel took the same count is drawn
// over count - 1 .. count + 1 (never below 0). `title` is drawn above
// verbatim. Throws caustica::Error naming `path`, and both sizes when spp
// does not hold width * height counts.
void write_spp_heatmap(const std::string& path, int width, int height, const std::vector<uint32_t>& spp,
                       const std::string& title);

}  // namespace caustica
