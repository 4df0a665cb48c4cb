// The pass driver: runs an integrator over the image, pass after pass.
//
// Rules: a pass is one sample of every pixel, traced chunk by chunk (the
// integrator's chunk size bounds queue memory), and a wave is as many
// passes as the integrator traces at once (Integrator::wave_passes; one for
// all but path mode), capped by the passes left, by the time limit and by
// the film (Film::most_passes_from: waves grow 1, 1, 2, 4, ... along the
// half buffer's powers of two). Without a time limit the waves depend on
// the pass count only, so a seed and spp give the same bits anywhere. A chunk whose queues
// overflowed is cleared from the pass in progress, and only from it, then
// traced again in halves, so a finished pass is never lost or counted twice.
// With adaptive sampling a wave keeps its pass count (pixels x passes
// samples) but spreads them by the film's error estimate, so the film's
// passes() is the mean count and the milestones stay those of a uniform
// render. After each wave the film accumulates it; progress is reported after every
// chunk; the driver stops after the requested passes, at the time limit, or
// when the pass-done callback says so (a target error), whichever first.
//
// The time limit T is kept within max(0.5 s, 5% of T) (issue 19): a wave is
// started only if its passes, each as long as a pass of the latest wave of
// its kind (Integrator::next_pass_kind; the longest pass so far for a kind
// not seen yet), would end within 3/4 of that tolerance after T (it is cut
// to the passes that do), and a pass still running at T plus 9/10 of it is
// abandoned between chunks (its contributions cleared, never accumulated).
// The first pass of a run always runs to the end.
//
// Adaptive sampling places a wave's samples from the film the previous wave
// left. Between the sampler's weight refreshes that is only the pixels'
// counts, which the host knows once a wave is planned, so the next wave is
// placed on a host thread while the device traces the current one (on a
// GPU the device otherwise waited for it: about 10 ms a wave at 512^2, more
// than the wave itself); it is taken only if the next wave is the one
// predicted, with the same counts, so the bits do not depend on it.
#pragma once

#include <cstdint>

#include <functional>
#include <future>

#include <optional>

#include "host/render/adaptive_sampling.h"
#include "host/render/film.h"
#include "host/render/integrator.h"
#include "host/render/pixel_share.h"

namespace caustica {

struct PassProgress {
  int pass = 0;  // 0-based pass in progress
  int passes = 0;  // the target (with a time limit the render may stop before)
  double seconds = 0.0;       // since the driver started
  double time_limit_s = 0.0;  // 0: none
  size_t pixels_done = 0;  // of this pass
  size_t pixels_total = 0;
  const RenderStats* stats = nullptr;
  int first_pass = 0;  // the film's passes when this run started (a resumed render's)
};
using ProgressCallback = std::function<void(const PassProgress&)>;
// After each accumulated wave (the film holds film.passes() passes).
// Returns false to end the render there (a target error reached).
using PassDoneCallback = std::function<bool(const Film& film, double seconds)>;

// The driver stops at whichever comes first.
struct StopConditions {
  // Absolute pass indices: the run adds passes [max(first_pass, the end of
  // the film's held passes), passes), so a film of [0, N) resumed goes on
  // from N, and a render of a subset of passes traces [first_pass, passes).
  int passes = 1;
  int first_pass = 0;
  double seconds = 0.0;  // wall-time limit (above; at least one pass runs); 0: none
};

// A render shared among processes (mpirun's ranks, issue 40;
// docs/distributed.md). Every process runs the driver with the same stop
// conditions, so it plans the waves one process would, and traces its part
// of each: an even wave's pixels share_of (every pass of them; a photon
// map's pass is such a wave, so each pixel's visible point and statistics
// stay with one process), an uneven wave's pixels samples_share_of (equal
// shares of its samples). Each film sums only what its process traced but
// counts every pixel's samples, so the films summed are one process's
// film, bit for bit. What one process decides from its clock (a wave cut
// to a time limit, whether to go on) rank 0 decides for all (broadcast),
// and the adaptive sampler's weights come from the whole film.
struct WaveShare {
  PixelShare* group = nullptr;
  // Called on every process where the sampler refreshes its weights (the
  // same waves on all): a collective that returns the whole film's weights
  // (AdaptiveSampler::weights_of with the group: the films summed) on every
  // process.
  std::function<std::vector<double>(const Film&)> weights;
  // Rank 0 decides after every wave (a time limit, an error monitor,
  // outputs due): its pass-done answer and its clock are broadcast. False:
  // the processes never talk between waves but for the weights.
  bool decides = false;
};

// How far past a time limit T a render may end: max(0.5 s, 5% of T).
double time_limit_tolerance(double limit_s);

class PassDriver {
 public:
  PassDriver(Integrator& integrator, Film& film, StageLauncher& launcher)
      : integrator_(integrator), film_(film), launcher_(launcher) {}
  // Adaptive sampling (host/render/adaptive_sampling.h): once every pixel
  // has options.min_spp samples, each wave the integrator lets be uneven
  // (Integrator::wave_may_be_uneven) is spread by the film's error
  // estimate; the film needs its half buffer.
  void set_adaptive(const AdaptiveOptions& options) { adaptive_.emplace(options); }
  // The adaptive sampler (nullptr without adaptive sampling): its state is
  // part of a render's (host/render/render_state.h).
  AdaptiveSampler* adaptive() { return adaptive_ ? &*adaptive_ : nullptr; }
  const AdaptiveSampler* adaptive() const { return adaptive_ ? &*adaptive_ : nullptr; }
  // Shares every wave among processes (WaveShare above); pass_done is then
  // called on every process after every wave.
  void share_waves(WaveShare share) { share_ = std::move(share); }
  // Adds passes to the film (it is not cleared here) until it holds
  // stop.passes: a film restored from a state goes on from its passes, with
  // the waves an uninterrupted render would have traced from there.
  void run(const StopConditions& stop, RenderStats* stats, const ProgressCallback& progress = {},
           const PassDoneCallback& pass_done = {});

 private:
  void trace_chunk(size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats);
  struct PlanAhead {
    int pass = -1, wave = 0;
    std::vector<uint32_t> spp;  // the counts it was placed from
    std::future<std::vector<uint32_t>> samples;
  };
  void start_plan_ahead(PlanAhead& ahead, const StopConditions& stop, int pass, int wave);
  std::optional<std::vector<uint32_t>> take_plan_ahead(PlanAhead& ahead, int pass, int wave, bool uneven);
  // An uneven wave's counts: AdaptiveSampler::plan, its weights from the
  // whole film when shared.
  std::vector<uint32_t> plan_uneven(int wave);
  // The pixels this process traces of the planned wave (all of them alone).
  std::pair<size_t, size_t> traced_pixels(const std::vector<uint32_t>& samples) const;

  Integrator& integrator_;
  Film& film_;
  StageLauncher& launcher_;
  std::optional<AdaptiveSampler> adaptive_;
  WaveShare share_;
};

}  // namespace caustica
