#include "host/render/pass_driver.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <limits>
#include <map>

#include "host/error.h"

namespace caustica {

void PassDriver::trace_chunk(size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats) {
  if (integrator_.trace_chunk(film_, first_pixel, pixel_count, passes, stats)) return;
  if (pixel_count <= 1) throw Error("render: ray queue overflow on a single pixel (capacity too small)");
  film_.clear_pass_range(first_pixel, pixel_count);
  if (stats) ++stats->chunk_retries;
  const size_t half = pixel_count / 2;
  trace_chunk(first_pixel, half, passes, stats);
  trace_chunk(first_pixel + half, pixel_count - half, passes, stats);
}

double time_limit_tolerance(double limit_s) { return std::max(0.5, 0.05 * limit_s); }

// The next uneven wave as it will be if nothing changes the plan (no time
// limit trimming it, the photon maps' schedule as it stands), placed on a
// host thread from the counts this wave and the uniform passes before it
// leave, while the device traces them.
void PassDriver::start_plan_ahead(PlanAhead& ahead, const StopConditions& stop, int pass, int wave) {
  const Integrator::UnevenWaveGuess guess = integrator_.next_uneven_wave(film_, wave);
  const int next_pass = pass + wave + guess.uniform_passes;
  if (guess.passes < 1 || next_pass >= stop.passes ||
      adaptive_->needs_weights(film_.passes() + wave + guess.uniform_passes))
    return;
  const int next_wave = Film::most_passes_from(next_pass, std::min(guess.passes, stop.passes - next_pass));
  if (next_wave < 1) return;
  ahead.pass = next_pass;
  ahead.wave = next_wave;
  ahead.spp = film_.spp_after_wave();
  for (uint32_t& n : ahead.spp) n += uint32_t(guess.uniform_passes);
  const AdaptiveSampler* sampler = &*adaptive_;
  ahead.samples = std::async(std::launch::async,
                             [sampler, spp = ahead.spp, next_wave] { return sampler->place(spp, next_wave); });
}

// The wave placed ahead, if it is the one about to be traced (same first
// pass, passes and counts, and weights that plan() would not read again):
// then plan() would return the same counts, since place() is what it does.
// A uniform wave before the one placed ahead (a photon map's pass) leaves
// it running: no plan() is made meanwhile.
std::optional<std::vector<uint32_t>> PassDriver::take_plan_ahead(PlanAhead& ahead, int pass, int wave, bool uneven) {
  if (!ahead.samples.valid() || (!uneven && pass < ahead.pass)) return std::nullopt;
  std::vector<uint32_t> samples = ahead.samples.get();  // (joined either way: plan() may change the weights)
  if (!uneven || ahead.pass != pass || ahead.wave != wave || adaptive_->needs_weights(film_.passes()) ||
      ahead.spp != film_.pixel_spp())
    return std::nullopt;
  return samples;
}

std::vector<uint32_t> PassDriver::plan_uneven(int wave) {
  if (share_.weights && adaptive_->needs_weights(film_.passes()))
    adaptive_->restore({share_.weights(film_), film_.passes()});
  return adaptive_->plan(film_, wave);
}

std::pair<size_t, size_t> PassDriver::traced_pixels(const std::vector<uint32_t>& samples) const {
  const size_t pixels = film_.pixel_count();
  if (!share_.group) return {0, pixels};
  const int rank = share_.group->rank(), size = share_.group->size();
  return samples.empty() ? share_of(pixels, rank, size) : samples_share_of(samples, rank, size);
}

void PassDriver::run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress,
                     const PassDoneCallback& pass_done) {
  const size_t pixels = film_.pixel_count();
  const size_t chunk = std::max<size_t>(1, integrator_.chunk_pixels());
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  const bool timed = stop.seconds > 0.0;
  const double tolerance = timed ? time_limit_tolerance(stop.seconds) : 0.0;
  // Shared among processes, rank 0's clock decides for all (WaveShare).
  PixelShare* const group = share_.group;
  const bool agreed = group && share_.decides;
  std::map<int, double> latest_pass_s;  // seconds a pass, by kind (of the latest wave of that kind)
  double longest_pass_s = 0.0;
  // The waves depend on the absolute pass index only (without a time
  // limit), so a resumed run traces the waves an uninterrupted one would
  // have, and a run of a subset of passes those passes' waves.
  const int first_pass = std::max(stop.first_pass, film_.held().end());
  const int first_count = film_.passes();
  // Progress counts the film's passes: the target is the count at the end.
  const bool open_ended = stop.passes == std::numeric_limits<int>::max();
  const int target = open_ended ? stop.passes : first_count + std::max(0, stop.passes - first_pass);
  PlanAhead ahead;
  for (int pass = first_pass; pass < stop.passes;) {
    const int kind = integrator_.next_pass_kind(film_);
    const double start = seconds();
    int wave = Film::most_passes_from(pass, std::min(integrator_.wave_passes(film_), stop.passes - pass));
    if (timed && pass > first_pass) {
      const auto known = latest_pass_s.find(kind);
      const double predicted = known != latest_pass_s.end() ? known->second : longest_pass_s;
      const double room = stop.seconds + 0.75 * tolerance - start;
      if (predicted > room) wave = 0;
      else if (predicted > 0.0) wave = std::max(1, std::min(wave, int(room / predicted)));
    }
    if (agreed && timed) wave = group->broadcast(wave);
    if (wave == 0) break;
    const bool uneven = adaptive_ && film_.has_half_buffer() &&
                        film_.passes() >= int(adaptive_->options().min_spp) && integrator_.wave_may_be_uneven(film_);
    std::optional<std::vector<uint32_t>> placed = take_plan_ahead(ahead, pass, wave, uneven);
    std::vector<uint32_t> samples = !uneven ? std::vector<uint32_t>{} : placed ? std::move(*placed) : plan_uneven(wave);
    // This process's pixels of the wave: their samples are listed for the
    // stages once the film is uneven; before, its chunks cover them.
    const auto [first_pixel, pixel_end] = traced_pixels(samples);
    film_.plan_wave(wave, std::move(samples), pass, {first_pixel, pixel_end});
    if (uneven) start_plan_ahead(ahead, stop, pass, wave);
    integrator_.begin_pass(film_, stats);
    bool abandoned = false;
    for (size_t first = first_pixel; first < pixel_end; first += chunk) {
      // (shared, the processes could not agree on a wave abandoned mid-way)
      if (timed && !group && pass > first_pass && first > first_pixel && seconds() > stop.seconds + 0.9 * tolerance) {
        abandoned = true;
        break;
      }
      trace_chunk(first, std::min(chunk, pixel_end - first), wave, stats);
      if (progress)
        progress(PassProgress{film_.passes() + wave - 1, target, seconds(), stop.seconds,
                              std::min(pixels, first + chunk), pixels, stats, first_count});
    }
    if (abandoned) {
      film_.abandon_wave();
      break;
    }
    integrator_.end_pass(film_, wave, stats);
    film_.accumulate_pass(launcher_, stats, wave);
    if (stats) stats->passes += wave;
    pass += wave;
    const double took = (seconds() - start) / wave;
    latest_pass_s[kind] = took;
    longest_pass_s = std::max(longest_pass_s, took);
    int go = !pass_done || pass_done(film_, seconds());
    if (timed && seconds() >= stop.seconds) go = 0;
    if (agreed) go = group->broadcast(go);
    if (!go) break;
  }
}

}  // namespace caustica
