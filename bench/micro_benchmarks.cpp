// Google Benchmark micro-benchmarks of the host-side stages (scene parse,
// BVH build, tone mapping) on the seed report's Table 1 scenes, adaptive
// sampling's plan between waves (weights, then placing a wave's samples)
// at 128^2 and 512^2, and the BVH
// build and collapse on the Conference room of bench/scenes (skipped when
// ../shared is not beside the checkout). Kernel
// throughput is measured by `caustica bench`, which times the renderer's own
// launches on a real scene.
#include <benchmark/benchmark.h>

#include <optional>
#include <random>

#include "host/accel/bvh.h"
#include "host/lights/light_tree.h"
#include "host/accel/bvh_wide.h"
#include "host/image/tonemap.h"
#include "host/render/adaptive_sampling.h"
#include "host/scene/generate.h"
#include "host/scene/load_scene.h"

namespace {

// The issue-4 benchmark scene with the largest mesh, loaded once.
const caustica::Scene* conference_scene() {
  static const std::optional<caustica::Scene> scene = []() -> std::optional<caustica::Scene> {
    try {
      return caustica::load_scene(CAUSTICA_SOURCE_DIR "/bench/scenes/conference_inside.json");
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }();
  return scene ? &*scene : nullptr;
}

caustica::Scene table1_scene(int shapes) {
  const auto json = caustica::generate_table1_scene(shapes, shapes != 400, 1);
  return caustica::parse_scene(json, "generated", ".");
}

void BM_ParseScene(benchmark::State& state) {
  const auto json = caustica::generate_table1_scene(int(state.range(0)), true, 1);
  for (auto _ : state) benchmark::DoNotOptimize(caustica::parse_scene(json, "generated", "."));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ParseScene)->Arg(400)->Arg(1600)->Arg(6400)->Arg(12800)->Unit(benchmark::kMillisecond);

void BM_BuildBvh(benchmark::State& state) {
  const caustica::Scene scene = table1_scene(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(caustica::build_bvh(scene));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_BuildBvh)->Arg(400)->Arg(1600)->Arg(6400)->Arg(12800)->Unit(benchmark::kMillisecond);

// The three BvhBuildOptions qualities (0 Fast, 1 Sah, 2 Spatial) on the
// 12,800-shape scene, all threads; the counters show what each buys.
void BM_BuildBvhQuality(benchmark::State& state) {
  const caustica::Scene scene = table1_scene(12800);
  caustica::BvhBuildOptions options;
  options.quality = caustica::BvhBuildOptions::Quality(state.range(0));
  caustica::Bvh bvh;
  for (auto _ : state) {
    bvh = caustica::build_bvh(scene, options);
    benchmark::DoNotOptimize(bvh.nodes.data());
  }
  state.counters["sah_cost"] = bvh.sah_cost;
  state.counters["references"] = double(bvh.references);
  state.SetItemsProcessed(state.iterations() * 12800);
}
BENCHMARK(BM_BuildBvhQuality)->ArgName("quality")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// Collapse of the 12,800-shape SBVH to the 8-wide layout: 0 the cost-driven
// dynamic program (default), 1 the greedy rule; the counters give the
// resulting tree (SAH in Embree's normalisation, wide nodes, leaf blocks).
void BM_CollapseWide(benchmark::State& state) {
  const caustica::Scene scene = table1_scene(12800);
  caustica::BvhBuildOptions build;
  build.quality = caustica::BvhBuildOptions::Quality::Spatial;
  const caustica::Bvh bvh = caustica::build_bvh(scene, build);
  caustica::WideBvhOptions options;
  options.collapse = state.range(0) == 0 ? caustica::WideBvhOptions::Collapse::Sah
                                         : caustica::WideBvhOptions::Collapse::Greedy;
  caustica::WideBvh wide;
  for (auto _ : state) {
    wide = caustica::collapse_bvh(bvh, scene, options);
    benchmark::DoNotOptimize(wide.nodes.data());
  }
  state.counters["sah"] = wide.node_sah + wide.leaf_sah;
  state.counters["wide_nodes"] = double(wide.nodes.size());
  state.counters["blocks"] = double(wide.triangle_blocks.size());
  state.SetItemsProcessed(state.iterations() * int64_t(bvh.nodes.size()));
}
BENCHMARK(BM_CollapseWide)->ArgName("greedy")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Binary build (0 Fast, 2 Spatial) then collapse of the Conference room, the
// two parts `caustica bench` reports as build_ms and collapse_ms.
void BM_BuildConference(benchmark::State& state) {
  const caustica::Scene* scene = conference_scene();
  if (!scene) {
    state.SkipWithError("bench/scenes/conference_inside.json needs ../shared/models");
    return;
  }
  caustica::BvhBuildOptions options;
  options.quality = caustica::BvhBuildOptions::Quality(state.range(0));
  double build_ms = 0.0, collapse_ms = 0.0;
  for (auto _ : state) {
    const caustica::Bvh bvh = caustica::build_bvh(*scene, options);
    const caustica::WideBvh wide = caustica::collapse_bvh(bvh, *scene, {});
    build_ms += bvh.build_ms;
    collapse_ms += wide.collapse_ms;
    benchmark::DoNotOptimize(wide.nodes.data());
  }
  state.counters["build_ms"] = build_ms / double(state.iterations());
  state.counters["collapse_ms"] = collapse_ms / double(state.iterations());
}
BENCHMARK(BM_BuildConference)->ArgName("quality")->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_ToDisplay(benchmark::State& state) {
  caustica::ImageF image(1200, 800, 0.3f);
  caustica::DisplaySettings d;
  d.tonemap = caustica::ToneMap(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(caustica::to_display(image, d));
  state.SetItemsProcessed(state.iterations() * image.pixel_count());
}
BENCHMARK(BM_ToDisplay)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

// Adaptive sampling between two waves, on a film of side x side pixels after
// 16-64 spp: the errors heavy-tailed as a render's are (log-normal, a few
// fireflies), the ray counts 1-8 a sample. The device waits for this plan
// (host/render/pass_driver.cpp), so on a GPU it is the render's host time.
caustica::AdaptiveInputs adaptive_inputs(int side) {
  caustica::AdaptiveInputs in;
  in.width = in.height = side;
  const size_t pixels = size_t(side) * size_t(side);
  std::mt19937 rng(7);
  std::lognormal_distribution<double> error(-9.0, 2.0);
  std::uniform_int_distribution<uint32_t> spp(16, 64), rays(1, 8);
  for (size_t p = 0; p < pixels; ++p) {
    in.pixel_error.push_back(error(rng));
    in.spp.push_back(spp(rng));
    in.rays.push_back(uint64_t(in.spp.back()) * rays(rng));
  }
  return in;
}

void BM_AdaptiveWeights(benchmark::State& state) {
  const caustica::AdaptiveInputs in = adaptive_inputs(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(caustica::neyman_weights(in, {}));
  state.SetItemsProcessed(state.iterations() * int64_t(in.spp.size()));
}
BENCHMARK(BM_AdaptiveWeights)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);

// One wave of 16 passes placed (the wave at 512^2 is 16 passes).
void BM_AdaptivePlaceWave(benchmark::State& state) {
  const caustica::AdaptiveInputs in = adaptive_inputs(int(state.range(0)));
  const std::vector<double> weights = caustica::neyman_weights(in, {});
  for (auto _ : state) benchmark::DoNotOptimize(caustica::place_wave_samples(weights, in.spp, 16, 1u << 20, {}));
  state.SetItemsProcessed(state.iterations() * int64_t(in.spp.size()));
}
BENCHMARK(BM_AdaptivePlaceWave)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);

// The light tree's build (issue 42; target: 100,000 emissive triangles in
// 50 ms): triangles of an emissive grid of screens, each light 1 to 1000
// in power, as build_light_table hands them over.
static void BM_BuildLightTree(benchmark::State& state) {
  const int count = int(state.range(0));
  std::vector<::Light> lights(size_t(count), ::Light{});
  std::vector<float> power(static_cast<size_t>(count));
  uint32_t h = 12345u;
  auto next = [&h] { h = h * 1664525u + 1013904223u; return float(h >> 8) / float(1u << 24); };
  for (int i = 0; i < count; ++i) {
    const float x = float(i % 316), y = float((i / 316) % 316), z = 4.0f * next();
    ::Light& l = lights[size_t(i)];
    l.kind = LIGHT_TRIANGLE;
    l.p0 = cs_float4{x, y, z, 0.0f};
    l.p1 = cs_float4{x + 0.8f, y + 0.1f * next(), z, 0.0f};
    l.p2 = cs_float4{x, y + 0.8f, z + 0.3f * next(), 0.0f};
    power[size_t(i)] = 1.0f + 999.0f * next();
  }
  for (auto _ : state) benchmark::DoNotOptimize(caustica::build_light_tree(lights, power));
}
BENCHMARK(BM_BuildLightTree)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
