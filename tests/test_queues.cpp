// Work-queue semantics, kernel-level: every push lands in a distinct slot,
// the counter equals the number of pushes, and pushes past the capacity are
// dropped without writing out of bounds while the counter still reports them
// (the host's overflow signal). Plus the renderer's use of that signal:
// chunks that overflow are redone and give the same image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <numeric>

#include "host/app/session.h"
#include "host/render/renderer.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

struct PushResult {
  uint32_t count;
  std::vector<uint32_t> slots;  // capacity + 16 guard entries
};

PushResult run_push(uint32_t n, uint32_t capacity, size_t local) {
  Runtime& rt = test::runtime();
  auto built = test::build_test_kernel("queues_push.cl", "", rt);
  cl::Kernel k(built.program, "push_test");
  const uint32_t guard = 16;
  std::vector<uint32_t> init(capacity + guard, 0xDEADBEEFu);
  cl::Buffer slots(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, init.size() * 4, init.data());
  uint32_t zero = 0;
  cl::Buffer count(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(zero), &zero);
  k.setArg(0, count);
  k.setArg(1, capacity);
  k.setArg(2, slots);
  k.setArg(3, n);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, local)), cl::NDRange(local));
  PushResult r;
  r.slots.resize(init.size());
  rt.queue().enqueueReadBuffer(count, CL_TRUE, 0, 4, &r.count);
  rt.queue().enqueueReadBuffer(slots, CL_TRUE, 0, init.size() * 4, r.slots.data());
  return r;
}

uint32_t expected_pushes(uint32_t n) {
  uint32_t total = 0;
  for (uint32_t i = 0; i < n; ++i) total += i % 4;
  return total;
}

TEST(WorkQueue, EveryPushGetsADistinctSlot) {
  for (size_t local : {1, 8, 64}) {
    const uint32_t n = 10007;  // not a multiple of any local size: padding must be inert
    const uint32_t pushes = expected_pushes(n);
    const PushResult r = run_push(n, pushes, local);
    EXPECT_EQ(r.count, pushes) << "local size " << local;
    std::vector<uint32_t> tags(r.slots.begin(), r.slots.begin() + pushes);
    std::sort(tags.begin(), tags.end());
    std::vector<uint32_t> want;
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t k = 0; k < i % 4; ++k) want.push_back((i << 2) | k);
    std::sort(want.begin(), want.end());
    EXPECT_EQ(tags, want) << "local size " << local;
    for (size_t g = pushes; g < r.slots.size(); ++g) EXPECT_EQ(r.slots[g], 0xDEADBEEFu);
  }
}

TEST(WorkQueue, OverflowIsCountedButNeverWrittenPastCapacity) {
  const uint32_t n = 5000, capacity = 1000;
  const PushResult r = run_push(n, capacity, 16);
  EXPECT_EQ(r.count, expected_pushes(n));  // > capacity: the host's overflow signal
  for (uint32_t s = 0; s < capacity; ++s) EXPECT_NE(r.slots[s], 0xDEADBEEFu) << s;
  for (size_t g = capacity; g < r.slots.size(); ++g) EXPECT_EQ(r.slots[g], 0xDEADBEEFu);
}

// A scene whose Fresnel splits more than double the queue (glass spheres
// seen through glass) forces chunk retries when the capacity equals the
// chunk, in each of several passes; the retries clear only the pass in
// progress, so the result must equal a render with ample capacity, bit for bit.
TEST(PassDriver, QueueOverflowRetriesGiveTheSameImage) {
  const std::string scene = test::temp_dir() + "/glass.json";
  {
    std::ofstream out(scene);
    // 24 x 16 on Oclgrind: the queues still overflow at capacity factor 1.
    out << R"({"nbounces": 6, "rendermode": "phong",
      "camera": {"type": "pinhole", "width": )"
        << test::sized(64, 24) << R"(, "height": )" << test::sized(48, 16) << R"(, "position": [0, 0, -3],
                 "lookAt": [0, 0, 0], "upVector": [0, 1, 0], "fov": 40, "exposure": 0},
      "scene": {"backgroundcolor": [0.3, 0.4, 0.5],
        "lightsources": [{"type": "pointlight", "position": [2, 3, -2], "intensity": [1, 1, 1]}],
        "shapes": [
          {"type": "sphere", "center": [0, 0, 0], "radius": 1.0,
           "material": {"isrefractive": true, "refractiveindex": 1.5, "diffusecolor": [1, 1, 1]}},
          {"type": "sphere", "center": [0.3, 0.2, 2.5], "radius": 1.2,
           "material": {"isrefractive": true, "refractiveindex": 1.33, "diffusecolor": [1, 1, 1]}},
          {"type": "triangle", "v0": [-5, -1.5, -5], "v1": [5, -1.5, 10], "v2": [5, -1.5, -5],
           "material": {"diffusecolor": [0.8, 0.3, 0.3]}}]}})";
  }
  SessionOptions o;
  o.scene_path = scene;
  o.device = test::device_spec();
  auto render = [&](float capacity_factor, RenderStats* stats) {
    auto s = prepare_session(o);
    RenderSettings settings = s->settings;
    settings.queue_capacity_factor = capacity_factor;
    settings.passes = 3;
    Renderer r(*s->runtime, *s->device_scene, s->mode, s->program.program, settings);
    return r.render(stats);
  };
  RenderStats tight, ample;
  const ImageF a = render(1.0f, &tight);
  const ImageF b = render(64.0f, &ample);
  EXPECT_GT(tight.chunk_retries, 0);
  EXPECT_EQ(ample.chunk_retries, 0);
  EXPECT_EQ(tight.passes, 3);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(0, std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)));
}

}  // namespace
}  // namespace caustica
