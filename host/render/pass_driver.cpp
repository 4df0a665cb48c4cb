#include "host/render/pass_driver.h"

#include <algorithm>
#include <chrono>

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

void PassDriver::run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress,
                     const PassDoneCallback& pass_done) {
  const size_t pixels = film_.pixel_count();
  const size_t chunk = std::max<size_t>(1, integrator_.chunk_pixels());
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  for (int pass = 0; pass < stop.passes; ++pass) {
    integrator_.begin_pass(film_, stats);
    for (size_t first = 0; first < pixels; first += chunk) {
      trace_chunk(first, std::min(chunk, pixels - first), stats);
      if (progress)
        progress(PassProgress{pass, stop.passes, seconds(), stop.seconds, std::min(pixels, first + chunk), pixels,
                              stats});
    }
    integrator_.end_pass(film_, stats);
    film_.accumulate_pass(launcher_, stats);
    if (stats) ++stats->passes;
    if (pass_done && !pass_done(film_, seconds())) break;
    if (stop.seconds > 0.0 && seconds() >= stop.seconds) break;
  }
}

}  // namespace caustica
