#include "host/render/pass_driver.h"

#include <algorithm>

#include "host/error.h"

namespace caustica {

void PassDriver::trace_chunk(size_t first_pixel, size_t pixel_count, RenderStats* stats) {
  if (integrator_.trace_chunk(film_, first_pixel, pixel_count, stats)) return;
  if (pixel_count <= 1) throw Error("render: ray queue overflow on a single pixel (capacity too small)");
  film_.clear_pass_range(first_pixel, pixel_count);
  if (stats) ++stats->chunk_retries;
  const size_t half = pixel_count / 2;
  trace_chunk(first_pixel, half, stats);
  trace_chunk(first_pixel + half, pixel_count - half, stats);
}

void PassDriver::run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress) {
  const size_t pixels = film_.pixel_count();
  const size_t chunk = std::max<size_t>(1, integrator_.chunk_pixels());
  for (int pass = 0; pass < stop.passes; ++pass) {
    for (size_t first = 0; first < pixels; first += chunk) {
      trace_chunk(first, std::min(chunk, pixels - first), stats);
      if (progress) progress(PassProgress{pass, stop.passes, std::min(pixels, first + chunk), pixels, stats});
    }
    film_.accumulate_pass(&launcher_, stats);
    if (stats) ++stats->passes;
  }
}

}  // namespace caustica
