#include "host/render/wave_loop.h"

#include <algorithm>

#include "host/cl/runtime.h"
#include "host/render/integrator.h"

namespace caustica {

WaveLoop::WaveLoop(StageLauncher& launcher, const std::vector<int>& extra_values) : launcher_(launcher) {
  cl::Context& ctx = launcher.runtime().context();
  // Sub-buffers start at multiples of the device's base address alignment.
  const cl_uint align_bits = ctx.getInfo<CL_CONTEXT_DEVICES>().at(0).getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>();
  int most_values = 1;
  for (int v : extra_values) most_values = std::max(most_values, v);
  stride_ = std::max<size_t>(align_bits / 8, most_values * sizeof(cl_uint));
  stride_ = (stride_ + align_bits / 8 - 1) / (align_bits / 8) * (align_bits / 8);
  const size_t counters = 3 + extra_values.size();
  counters_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, counters * stride_);
  launcher.runtime().fill(counters_, cl_uint(0), 0, counters * stride_);
  for (size_t c = 0; c < counters; ++c) {
    const size_t values = c < 3 ? 1 : size_t(std::max(1, extra_values[c - 3]));
    const cl_buffer_region region{c * stride_, values * sizeof(cl_uint)};
    counter_.push_back(counters_.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region));
  }
  for (Counters& read : reads_) {
    read.values_.assign(counters * stride_ / sizeof(cl_uint), 0);
    read.stride_words_ = stride_ / sizeof(cl_uint);
  }
}

bool WaveLoop::run(size_t first_bound, uint32_t max_iterations, const Enqueue& enqueue, const Decide& decide,
                   RenderStats* stats) {
  size_t bound = first_bound;
  bool stop = bound == kStop, overflow = false;
  uint32_t decided = 0;  // reads decided on: iterations [0, decided)
  auto decide_on = [&](uint32_t seen) {
    Counters& read = reads_[seen % (kCountLag + 1)];
    read.done_.wait();
    last_ = &read;
    const size_t next = decide(read, seen);
    if (next == kOverflow) overflow = true;
    else if (next == kStop) stop = true;
    else bound = next;
  };
  uint32_t j = 0;
  for (; j < max_iterations && !stop && !overflow; ++j) {
    enqueue(j, bound);
    Counters& read = reads_[j % (kCountLag + 1)];
    launcher_.read_async(counters_, read.values_.size() * sizeof(cl_uint), read.values_.data(), &read.done_, stats);
    if (j >= uint32_t(kCountLag)) decide_on(decided++);
  }
  for (; decided < j; ++decided) decide_on(decided);  // the last reads: overflow and final counters
  return !overflow;
}

}  // namespace caustica
