// `caustica bench`: BVH build, cold kernel build, ray throughput of the
// renderer's own traversal kernels on three host-generated ray sets (primary,
// diffuse, shadow; host/bench/bench_rays.h, shared with the Embree reference
// bench/embree/) and total render time. The last line of its output is one
// JSON object.
#pragma once

#include <string>

#include "host/app/session.h"

namespace caustica {

struct BenchArgs {
  SessionOptions session;
  std::string mode;
  int repetitions = 5;
};

int run_bench(BenchArgs& args);

}  // namespace caustica
