// A caustica Scene as an Embree 3 scene, traced with rtcIntersect1 /
// rtcOccluded1 over a few host threads: the reference that `caustica bench`
// figures are compared with (bench/run_embree_comparison.sh).
//
// Triangles are RTC_GEOMETRY_TYPE_TRIANGLE; spheres and cylinders are user
// geometry whose callbacks run caustica's own intersection math
// (host/bench/host_trace.h), so both tracers answer the same question for
// every primitive type. Embree builds with its defaults apart from the
// quality: RTC_BUILD_QUALITY_HIGH, scene flags RTC_SCENE_FLAG_NONE.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "host/bench/bench_rays.h"
#include "host/scene/scene.h"

namespace caustica {

class EmbreeScene {
 public:
  // threads: Embree's own worker threads (the build); tracing threads are
  // chosen per call. Throws caustica::Error on an Embree error.
  // quality: RTC_BUILD_QUALITY_HIGH (spatial splits) or _MEDIUM (rtcNewScene's default).
  EmbreeScene(const Scene& scene, int threads, RTCBuildQuality quality = RTC_BUILD_QUALITY_HIGH);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  double setup_ms() const { return setup_ms_; }  // geometry creation and data copies
  double build_ms() const { return build_ms_; }  // rtcCommitScene: the BVH build

  // Closest hit of every ray as a caustica prim reference (PRIM_NONE: miss),
  // over [0, rays.tmax(i)]; written to *prims (resized).
  void trace_closest(const RaySet& rays, int threads, std::vector<uint32_t>* prims) const;
  // 1 where [0, rays.tmax(i)] is blocked; written to *occluded (resized).
  void trace_occluded(const RaySet& rays, int threads, std::vector<uint8_t>* occluded) const;

 private:
  uint32_t prim_ref(unsigned geom_id, unsigned prim_id) const;

  const Scene& scene_;
  RTCDevice device_ = nullptr;
  RTCScene rtc_scene_ = nullptr;
  std::vector<uint32_t> geom_type_;  // geomID -> PRIM_* type
  double setup_ms_ = 0.0, build_ms_ = 0.0;
};

}  // namespace caustica
