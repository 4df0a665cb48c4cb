#include "bench/embree/embree_scene.h"

#if defined(__SSE3__) || defined(__x86_64__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define CAUSTICA_HAVE_MXCSR 1
#endif

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <string>

#include "host/bench/host_trace.h"
#include "host/error.h"
#include "host/parallel.h"

namespace caustica {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void check(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw Error(std::string("Embree: ") + what + " failed (RTCError " + std::to_string(err) + ")");
}

// Embree's tutorials run every tracing thread with denormals flushed; without
// it some rays take a slow path, and the reference would understate Embree.
// Scoped, because parallel_blocks also runs blocks on the calling thread,
// whose host reference traces must keep IEEE denormals.
class FlushDenormals {
#ifdef CAUSTICA_HAVE_MXCSR
 public:
  FlushDenormals() : saved_(_mm_getcsr()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~FlushDenormals() { _mm_setcsr(saved_); }

 private:
  unsigned saved_;
#endif
};

// Boxes rounded outward to float: Embree culls with them, and a box a hair
// too small would drop hits that caustica's conservative boxes keep.
void set_bounds(RTCBounds* b, const glm::dvec3& c, const glm::dvec3& e) {
  auto down = [](double x) { return std::nextafter(float(x), -std::numeric_limits<float>::max()); };
  auto up = [](double x) { return std::nextafter(float(x), std::numeric_limits<float>::max()); };
  b->lower_x = down(c.x - e.x);
  b->lower_y = down(c.y - e.y);
  b->lower_z = down(c.z - e.z);
  b->upper_x = up(c.x + e.x);
  b->upper_y = up(c.y + e.y);
  b->upper_z = up(c.z + e.z);
}

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const Scene& scene = *static_cast<const Scene*>(args->geometryUserPtr);
  const cs_float4 s = scene.spheres[args->primID].center_radius;
  set_bounds(args->bounds_o, glm::dvec3(to_vec3(s)), glm::dvec3(s.w));
}

void cylinder_bounds(const RTCBoundsFunctionArguments* args) {
  const Scene& scene = *static_cast<const Scene*>(args->geometryUserPtr);
  const Cylinder& c = scene.cylinders[args->primID];
  const glm::dvec3 a(to_vec3(c.axis_half));
  const double half = c.axis_half.w, r = c.center_radius.w;
  glm::dvec3 e;
  for (int i = 0; i < 3; ++i) e[i] = std::abs(a[i]) * half + r * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i]));
  set_bounds(args->bounds_o, glm::dvec3(to_vec3(c.center_radius)), e);
}

// One primitive against one ray, with caustica's math; *t holds tfar on
// input and receives the hit distance.
bool user_hit(const Scene& scene, bool sphere, unsigned prim, const RTCRay& ray, float* t) {
  const glm::vec3 o(ray.org_x, ray.org_y, ray.org_z), d(ray.dir_x, ray.dir_y, ray.dir_z);
  if (sphere) {
    const cs_float4 s = scene.spheres[prim].center_radius;
    return host_intersect_sphere(to_vec3(s), s.w, o, d, ray.tnear, t);
  }
  const Cylinder& c = scene.cylinders[prim];
  float part = 0.0f;
  return host_intersect_cylinder(to_vec3(c.center_radius), to_vec3(c.axis_half), c.center_radius.w, c.axis_half.w,
                                 o, d, ray.tnear, t, &part);
}

template <bool kSphere>
void user_intersect(const RTCIntersectFunctionNArguments* args) {
  // Only rtcIntersect1 is used: N is 1 and the ray hit is an RTCRayHit.
  if (args->N != 1 || !args->valid[0]) return;
  RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  const Scene& scene = *static_cast<const Scene*>(args->geometryUserPtr);
  float t = rh->ray.tfar;
  if (!user_hit(scene, kSphere, args->primID, rh->ray, &t)) return;
  rh->ray.tfar = t;
  rh->hit.Ng_x = rh->hit.Ng_y = rh->hit.Ng_z = 0.0f;  // not needed by the bench
  rh->hit.u = rh->hit.v = 0.0f;
  rh->hit.primID = args->primID;
  rh->hit.geomID = args->geomID;
  rh->hit.instID[0] = args->context->instID[0];
}

template <bool kSphere>
void user_occluded(const RTCOccludedFunctionNArguments* args) {
  if (args->N != 1 || !args->valid[0]) return;
  RTCRay* ray = reinterpret_cast<RTCRay*>(args->ray);
  const Scene& scene = *static_cast<const Scene*>(args->geometryUserPtr);
  float t = ray->tfar;
  if (user_hit(scene, kSphere, args->primID, *ray, &t)) ray->tfar = -std::numeric_limits<float>::infinity();
}

RTCRay make_ray(const RaySet& rays, size_t i) {
  RTCRay r{};
  r.org_x = rays.origin[i].x;
  r.org_y = rays.origin[i].y;
  r.org_z = rays.origin[i].z;
  r.tnear = 0.0f;
  r.dir_x = rays.dir[i].x;
  r.dir_y = rays.dir[i].y;
  r.dir_z = rays.dir[i].z;
  r.time = 0.0f;
  r.tfar = rays.tmax(i);
  r.mask = 0xFFFFFFFFu;
  r.flags = 0;
  return r;
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, int threads, RTCBuildQuality quality) : scene_(scene) {
  // EMBREE_CONFIG appends Embree's own device options (e.g. "verbose=2"
  // prints its BVH statistics: SAH cost, node counts, leaf fill).
  std::string config = "threads=" + std::to_string(std::max(1, threads));
  if (const char* extra = std::getenv("EMBREE_CONFIG")) config += std::string(",") + extra;
  device_ = rtcNewDevice(config.c_str());
  if (!device_)
    throw Error("Embree: rtcNewDevice failed (RTCError " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  const auto t0 = std::chrono::steady_clock::now();
  rtc_scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(rtc_scene_, quality);
  rtcSetSceneFlags(rtc_scene_, RTC_SCENE_FLAG_NONE);

  auto attach = [&](RTCGeometry geom, uint32_t type) {
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(rtc_scene_, geom);
    rtcReleaseGeometry(geom);
    if (geom_type_.size() <= id) geom_type_.resize(id + 1, PRIM_NONE);
    geom_type_[id] = type;
  };
  if (!scene.triangles.empty()) {
    const size_t n = scene.triangles.size();
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // caustica triangles are unindexed: three vertices of their own each.
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
    check(device_, "allocating the triangle buffers");
    for (size_t i = 0; i < n; ++i) {
      const cs_float4* p[3] = {&scene.triangles[i].v0, &scene.triangles[i].v1, &scene.triangles[i].v2};
      for (int k = 0; k < 3; ++k) {
        v[9 * i + 3 * k + 0] = p[k]->x;
        v[9 * i + 3 * k + 1] = p[k]->y;
        v[9 * i + 3 * k + 2] = p[k]->z;
        idx[3 * i + k] = unsigned(3 * i + k);
      }
    }
    attach(geom, PRIM_TRIANGLE);
  }
  if (!scene.spheres.empty()) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(scene.spheres.size()));
    rtcSetGeometryUserData(geom, const_cast<Scene*>(&scene));
    rtcSetGeometryBoundsFunction(geom, sphere_bounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, user_intersect<true>);
    rtcSetGeometryOccludedFunction(geom, user_occluded<true>);
    attach(geom, PRIM_SPHERE);
  }
  if (!scene.cylinders.empty()) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(scene.cylinders.size()));
    rtcSetGeometryUserData(geom, const_cast<Scene*>(&scene));
    rtcSetGeometryBoundsFunction(geom, cylinder_bounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, user_intersect<false>);
    rtcSetGeometryOccludedFunction(geom, user_occluded<false>);
    attach(geom, PRIM_CYLINDER);
  }
  check(device_, "creating the geometry");
  setup_ms_ = ms_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  rtcCommitScene(rtc_scene_);
  build_ms_ = ms_since(t1);
  check(device_, "rtcCommitScene");
}

EmbreeScene::~EmbreeScene() {
  if (rtc_scene_) rtcReleaseScene(rtc_scene_);
  if (device_) rtcReleaseDevice(device_);
}

uint32_t EmbreeScene::prim_ref(unsigned geom_id, unsigned prim_id) const {
  if (geom_id == RTC_INVALID_GEOMETRY_ID || geom_id >= geom_type_.size()) return PRIM_NONE;
  return (geom_type_[geom_id] << PRIM_TYPE_SHIFT) | (prim_id & PRIM_INDEX_MASK);
}

void EmbreeScene::trace_closest(const RaySet& rays, int threads, std::vector<uint32_t>* prims) const {
  prims->resize(rays.size());
  parallel_blocks(rays.size(), threads, [&](size_t begin, size_t end) {
    const FlushDenormals ftz;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = begin; i < end; ++i) {
      RTCRayHit rh;
      rh.ray = make_ray(rays, i);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtc_scene_, &context, &rh);
      (*prims)[i] = prim_ref(rh.hit.geomID, rh.hit.primID);
    }
  });
}

void EmbreeScene::trace_occluded(const RaySet& rays, int threads, std::vector<uint8_t>* occluded) const {
  occluded->resize(rays.size());
  parallel_blocks(rays.size(), threads, [&](size_t begin, size_t end) {
    const FlushDenormals ftz;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = begin; i < end; ++i) {
      RTCRay ray = make_ray(rays, i);
      rtcOccluded1(rtc_scene_, &context, &ray);
      (*occluded)[i] = ray.tfar < 0.0f ? 1 : 0;
    }
  });
}

}  // namespace caustica
