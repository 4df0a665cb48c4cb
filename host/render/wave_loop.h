// The bounce loop of the wavefront integrators, written once (issue 20).
//
// Rules: an integrator's iteration j is its stages (intersect, shade,
// shadow) over the rays of queue count j; the counts live on the device in
// three counters that rotate (iteration j traces count j mod 3, its shade
// stage pushes into j + 1 and clears j + 2), so the host writes nothing
// between iterations. The host launches each iteration over a bound it
// knows: after queueing iteration j it waits for the non-blocking read of
// the counters after iteration j - kCountLag, which the device finished
// while it worked on the iterations after it, and the integrator turns that
// read into the bound for the iterations to come, a stop (no rays left) or
// an overflow (a queue ran past its capacity: the chunk is traced again).
// Stages return at once past their count, so a bound above it only costs
// empty work-items. Besides the queue counts the counter buffer holds
// `extra` counters of the integrator's own (rays traced, samples started),
// each in its own sub-buffer, so one read carries them all.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace caustica {

class StageLauncher;
struct RenderStats;

class WaveLoop {
 public:
  static constexpr int kCountLag = 2;
  static constexpr size_t kStop = 0;
  static constexpr size_t kOverflow = ~size_t(0);

  // The counters after one iteration, as read back.
  class Counters {
   public:
    cl_uint queue_count(uint32_t iteration) const { return at(iteration % 3, 0); }
    cl_uint extra(int counter, int value = 0) const { return at(3 + counter, value); }

   private:
    friend class WaveLoop;
    cl_uint at(int counter, int value) const { return values_[counter * stride_words_ + value]; }
    std::vector<cl_uint> values_;
    size_t stride_words_ = 0;
    cl::Event done_;
  };

  // `extra_values[k]` uints in extra counter k (rays traced, ...); every
  // counter starts at zero.
  WaveLoop(StageLauncher& launcher, const std::vector<int>& extra_values);

  // Iteration j's counters for kernel arguments.
  const cl::Buffer& traced_count(uint32_t j) const { return counter_[j % 3]; }
  const cl::Buffer& pushed_count(uint32_t j) const { return counter_[(j + 1) % 3]; }
  const cl::Buffer& cleared_count(uint32_t j) const { return counter_[(j + 2) % 3]; }
  const cl::Buffer& extra(int counter) const { return counter_[3 + counter]; }

  // Iteration j's stages over `bound` work-items: the latest decision, or
  // first_bound up to iteration kCountLag (the integrator widens it there
  // where its queues can grow).
  using Enqueue = std::function<void(uint32_t j, size_t bound)>;
  // From the counters after iteration `seen`: the bound for the iterations
  // after seen + kCountLag, or kStop, or kOverflow.
  using Decide = std::function<size_t(const Counters& after, uint32_t seen)>;
  // Runs iterations 0, 1, ... up to max_iterations from first_bound; every
  // read is decided on, the last ones after the loop (an overflow there
  // still counts). False on an overflow. last() is then the counters after
  // the last iteration queued.
  bool run(size_t first_bound, uint32_t max_iterations, const Enqueue& enqueue, const Decide& decide,
           RenderStats* stats);
  const Counters& last() const { return *last_; }

 private:
  StageLauncher& launcher_;
  size_t stride_ = 0;  // bytes between counters: the device's sub-buffer alignment
  cl::Buffer counters_;
  std::vector<cl::Buffer> counter_;
  Counters reads_[kCountLag + 1];
  const Counters* last_ = nullptr;
};

}  // namespace caustica
