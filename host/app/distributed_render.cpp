#include "host/app/distributed_render.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <tuple>

#include "host/error.h"
#include "host/render/adaptive_sampling.h"
#include "host/render/render_state.h"
#include "host/render/state_merge.h"

namespace caustica {

namespace {

// The film's 128-bit sums, summed on rank 0. Their high words are zero
// unless a sum reached 2^64 (2^40 in radiance at the finest scale, 2^24):
// when every rank's are, and no rank's low word exceeds (2^64 - 1) / ranks,
// the low words alone add without overflow, and MPI's own 64-bit sum moves
// half the bytes; otherwise the 128-bit op. Exact either way.
void sum_film_sums_to_root(RankGroup& ranks, std::vector<uint64_t>& sums) {
  if (film_sums_need_128_bits(ranks, film_low_words_may_overflow(sums, ranks.size()))) {
    ranks.sum128_to_root(sums);
    return;
  }
  std::vector<uint64_t> low(sums.size() / 2);
  for (size_t i = 0; i < low.size(); ++i) low[i] = sums[2 * i];
  ranks.sum_to_root(low);
  if (ranks.rank() != 0) return;
  for (size_t i = 0; i < low.size(); ++i) {
    sums[2 * i] = low[i];
    sums[2 * i + 1] = 0;
  }
}

}  // namespace

FilmState reduce_film_to_root(RankGroup& ranks, FilmState mine, bool by_waves) {
  // The pass sets first: rank 0 forms the union (refusing overlaps: a
  // schedule bug must not double passes silently) and tells every rank its
  // last pass, which decides whose half buffer belongs to the union's.
  // Shared by pixels, every rank holds the same passes (of its own pixels).
  std::vector<int32_t> ranges;
  for (const auto& [b, e] : mine.held.ranges()) ranges.insert(ranges.end(), {b, e});
  const std::vector<std::vector<int32_t>> all = ranks.gather_to_root(ranges);
  PassSet held;
  for (size_t r = 0; r < all.size(); ++r) {
    PassSet rank_held;
    for (size_t i = 0; i + 1 < all[r].size(); i += 2) {
      const PassSet part = PassSet::range(all[r][i], all[r][i + 1]);
      if (!by_waves && held.overlaps(part))
        throw Error("rank " + std::to_string(r) + " traced pass " + std::to_string(held.first_common(part)) +
                    ", which another rank traced too");
      if (!by_waves) held.add(part);
      rank_held.add(part);
    }
    if (by_waves && !(rank_held == mine.held))
      throw Error("rank " + std::to_string(r) + " holds " + rank_held.describe() + " of its pixels, rank 0 " +
                  mine.held.describe());
  }
  if (by_waves && ranks.rank() == 0) held = mine.held;
  const int last = ranks.broadcast(held.last());
  FilmLayout layout;
  if (!FilmLayout::from_words(mine.spp.size(), mine.accumulated.size(), &layout))
    throw Error("a film of " + std::to_string(mine.spp.size()) + " pixels and " +
                std::to_string(mine.accumulated.size()) + " sum words, which no film layout has");
  const size_t values = layout.values();
  if (layout.half && !half_is_in_union(mine.held, last))
    std::fill(mine.accumulated.begin() + std::ptrdiff_t(2 * values), mine.accumulated.end(), 0u);
  sum_film_sums_to_root(ranks, mine.accumulated);
  // Shared by pixels: every rank counts every pixel's passes (its own
  // pixels' samples, the others' zero): rank 0's counts are the image's.
  if (!by_waves) ranks.sum_to_root(mine.spp);
  ranks.sum_to_root(mine.pixel_rays);
  ranks.sum_to_root(mine.counters);
  if (ranks.rank() != 0 || by_waves) return mine;  // by waves: rank 0's counts, halves and passes are the image's
  mine.held = held;
  mine.passes = held.count();
  mine.per_pixel = false;
  const int half = held.half_count();
  mine.half_start.assign(mine.spp.size(), half > 0 ? uint32_t(mine.passes - half) : 0u);
  return mine;
}

namespace {

// CAUSTICA_TEST_DIE_RANK=R (tests only): rank R exits with status 3 after
// the round that reaches 16 passes, as a crashed rank would, without
// telling the others (checkpoints of the rounds before stay).
void maybe_die_for_test(const RankGroup& ranks, int done) {
  const char* die = std::getenv("CAUSTICA_TEST_DIE_RANK");
  if (!die || std::atoi(die) != ranks.rank() || done < 16) return;
  std::fprintf(stderr, "caustica: rank %d: exiting as CAUSTICA_TEST_DIE_RANK asks\n", ranks.rank());
  std::fflush(stderr);
  std::_Exit(3);
}

}  // namespace

DistributedResult render_distributed(Session& session, RankGroup& ranks, RenderStats* stats,
                                     const ProgressCallback& progress, ErrorMonitor* monitor,
                                     const RenderState* resume, const DistributedOutputs& outputs) {
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  const RenderSettings& settings = session.settings;
  Renderer& renderer = *session.renderer;
  const int rank = ranks.rank(), size = ranks.size();
  DistributedResult out;
  // Path mode shares every wave among the ranks (pass_driver.h's
  // WaveShare: adaptive sampling and the photon pass keep one process's
  // schedule); binary and phong, one pass each, split passes in rounds.
  const bool by_waves = size > 1 && renderer.integrator().share_pixels(&ranks);
  out.by_waves = by_waves;
  if (rank == 0)
    out.summed = std::make_unique<Renderer>(*session.runtime, *session.device_scene, session.mode,
                                            session.program.program, settings);
  // Sums every rank's film into rank 0's `summed` renderer.
  // `for_state`: the summed renderer's state will be written (a
  // checkpoint), so by waves the ranks send every per-pixel value of the
  // photon pass, not only what the image and its error estimate read.
  auto reduce = [&](bool for_state) {
    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const auto r0 = Clock::now();
    FilmState mine = renderer.film().state();
    // By waves: each rank's window of the photon pass's per-pixel statistics.
    const std::string slice = by_waves ? renderer.integrator().pixel_slice(for_state) : std::string();
    out.read_seconds += since(r0);
    // The ranks' waves end apart: the wait is the imbalance, not MPI's cost.
    const auto waited = Clock::now();
    ranks.barrier();
    out.wait_seconds += since(waited);
    const auto r1 = Clock::now();
    RenderState state;
    state.film = reduce_film_to_root(ranks, std::move(mine), by_waves);
    const std::vector<std::string> slices = by_waves ? ranks.gather_bytes_to_root(slice) : std::vector<std::string>{};
    out.mpi_seconds += since(r1);
    const auto r2 = Clock::now();
    if (rank == 0) {
      // By waves: rank 0's own statistics and schedule (the same on every
      // rank) with every window's pixels: the whole image's, as one
      // process's; and its adaptive sampler's state, every rank's. By
      // passes the integrator keeps nothing a later pass needs (phong's
      // one pass, which rank 0 traced).
      if (by_waves) renderer.integrator().put_pixel_slices(slices);
      state.integrator = renderer.integrator().state();
      state.adaptive = renderer.adaptive_state();
      out.summed->begin(&state);
    }
    out.restore_seconds += since(r2);
    ++out.reductions;
    out.reduction_seconds += since(r0);
  };
  const int end = settings.passes;  // INT_MAX: open (a time limit or a target error ends it)
  const double limit = settings.time_limit_s;
  // Rank 0 decides after each wave or round (a time limit, its error
  // monitor, outputs due); with --spp alone the ranks talk at the end (and
  // by waves where the adaptive sampler refreshes its weights).
  const bool checkpoints = rank == 0 && outputs.checkpoint != nullptr;
  const bool writes = rank == 0 && outputs.write != nullptr;
  const bool decided = ranks.broadcast(rank == 0 && (limit > 0.0 || monitor || checkpoints || writes) ? 1 : 0) != 0;
  const double tolerance = limit > 0.0 ? time_limit_tolerance(limit) : 0.0;
  if (resume && !resume->film.held.is_prefix())
    throw Error("a state of " + resume->film.held.describe() + " resumes in one process only (ranks go on from "
                "passes [0, N))");
  double last_checkpoint = 0.0, last_write = 0.0;
  // After a wave or round (every rank): rank 0 decides whether to measure
  // or write now (every rank sums its film for it), measures and writes;
  // false: its error monitor says stop.
  auto measure_and_write = [&](int done) {
    const double now = seconds();
    const bool measure = rank == 0 && monitor && monitor->wants_measurement(done);
    const bool save = checkpoints && now - last_checkpoint >= outputs.checkpoint_every_s;
    const bool write = writes && now - last_write >= outputs.write_every_s;
    const int sum_now = ranks.broadcast(save ? 2 : measure || write ? 1 : 0);
    if (sum_now) reduce(sum_now == 2);
    if (save) {
      last_checkpoint = seconds();
      outputs.checkpoint(*out.summed);
    }
    if (write) {
      last_write = seconds();
      outputs.write(*out.summed, now);
    }
    if (!measure) return true;
    // The other ranks wait for this decision: its time is theirs too.
    const double measure_start = seconds();
    const bool go = monitor->on_pass(out.summed->film(), now);
    out.measure_seconds += seconds() - measure_start;
    return go;
  };
  if (by_waves) {
    // Every rank runs one process's waves over its part of each (the
    // driver's WaveShare), rank 0 deciding for all after each.
    WaveShare share;
    share.group = &ranks;
    share.decides = decided;
    if (settings.adaptive)
      share.weights = [&](const Film& film) {
        // The sampler's weights from the films summed on every rank (the
        // colour sums and the ray counts only; the photon pass's windows
        // gathered): O(log passes) times a render.
        // The ranks' waves since the last talk end apart: the wait is the
        // imbalance, apart from the refresh's own cost.
        const auto waited = std::chrono::steady_clock::now();
        ranks.barrier();
        const auto w0 = std::chrono::steady_clock::now();
        out.weight_wait_seconds += std::chrono::duration<double>(w0 - waited).count();
        const double mpi0 = ranks.collective_seconds();
        renderer.integrator().gather_shared_pixels();
        std::vector<double> weights = AdaptiveSampler::weights_of(film, settings.adaptive_options, &ranks);
        ++out.weight_refreshes;
        out.weight_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        out.weight_mpi_seconds += ranks.collective_seconds() - mpi0;
        return weights;
      };
    renderer.share_waves(std::move(share));  // (begin() hands it to the driver)
  }
  // The ranks go on from the resumed passes [0, N): rank 0 holds them.
  // By waves, every rank resumes the whole state (the film's counts, the
  // adaptive sampler's weights, the photon pass's schedule, map and its
  // window's statistics) but rank 0 alone the film's sums: the others'
  // start at zero.
  const int resumed = ranks.broadcast(rank == 0 && resume ? resume->film.held.end() : 0);
  if (by_waves && rank != 0 && resumed > 0) {
    // Rank 0 read the state; the others get its bytes.
    RenderState others = decode_render_state(ranks.gather_bytes_to_all(std::string()), "rank 0's resumed state");
    std::fill(others.film.accumulated.begin(), others.film.accumulated.end(), 0u);
    std::fill(others.film.pixel_rays.begin(), others.film.pixel_rays.end(), 0u);
    std::fill(others.film.counters.begin(), others.film.counters.end(), 0u);
    renderer.begin(&others);
    renderer.integrator().zero_shared_sums();
  } else {
    if (by_waves && resumed > 0) ranks.gather_bytes_to_all(encode_render_state(*resume));
    renderer.begin(rank == 0 ? resume : nullptr);
  }
  if (by_waves) {
    StopConditions stop;
    stop.passes = end;
    stop.seconds = limit;
    ProgressCallback shown;
    if (progress)
      shown = [&](const PassProgress& p) {
        PassProgress q = p;
        q.first_pass = resumed;
        progress(q);
      };
    renderer.run(stop, stats, rank == 0 ? shown : ProgressCallback{}, [&](const Film& film, double) {
      maybe_die_for_test(ranks, film.passes());
      return !decided || measure_and_write(film.passes());
    });
  } else {
    // Rank 0's progress as the whole group's: its passes since the start
    // (a resumed state's are its own) times the ranks.
    ProgressCallback shown;
    if (progress)
      shown = [&](const PassProgress& p) {
        PassProgress q = p;
        q.pass = int(std::min<int64_t>(int64_t(end) - 1, resumed + int64_t(p.pass - resumed) * size));
        q.passes = end;
        q.first_pass = resumed;
        progress(q);
      };
    const int most_block = std::max(1, renderer.integrator().wave_passes(renderer.film()));
    double round_s = 0.0;
    // Rounds end where rank 0 decides next: its error monitor's next
    // measurement (a round must not run far past a target error).
    int decide_at = end;
    for (int done = resumed; done < end;) {
      const double start = seconds();
      const int until_decision = int(std::max<int64_t>(1, (int64_t(decide_at) - done + size - 1) / size));
      const int block = std::clamp(std::min(done / size, until_decision), 1, most_block);
      const int64_t first = int64_t(done) + int64_t(rank) * block;
      const int64_t last = std::min<int64_t>(end, first + block);
      if (first < last) {
        StopConditions stop;
        stop.first_pass = int(first);
        stop.passes = int(last);
        renderer.run(stop, stats, rank == 0 ? shown : ProgressCallback{});
      }
      done = int(std::min<int64_t>(end, int64_t(done) + int64_t(size) * block));
      maybe_die_for_test(ranks, done);
      if (!decided) continue;
      round_s = seconds() - start;
      int go = measure_and_write(done) ? 1 : 0;
      if (rank == 0) {
        const double now = seconds();
        if (limit > 0.0 && (now >= limit || now + round_s > limit + 0.75 * tolerance)) go = 0;
      }
      // 0: stop; else where to decide next.
      const int next = rank == 0 && go ? (monitor ? std::max(done + 1, monitor->next_measurement()) : end) : 0;
      decide_at = ranks.broadcast(next);
      if (decide_at == 0) break;
    }
  }
  // The final state may be written (render_command.cpp's --checkpoint).
  reduce(ranks.broadcast(checkpoints ? 1 : 0) != 0);
  out.seconds = seconds();
  out.photon_traffic = renderer.integrator().shared_photon_traffic();
  if (rank == 0) out.image = out.summed->finish(stats);
  // By waves, rank 0's own photon counters are the render's (the maps
  // were gathered whole, the gather counters summed over the ranks; its
  // photon rays and seconds are its own share); the summed renderer's,
  // restored from a state, counted nothing.
  if (rank == 0 && by_waves) renderer.integrator().collect(stats);
  return out;
}

}  // namespace caustica
