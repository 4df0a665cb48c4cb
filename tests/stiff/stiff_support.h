// Shared by the stiff-case suite (issue 14): whole-scene transforms, renders
// of an edited scene, and closest hits through the real device traversal
// (the BVH the renderer builds, kernels/integrator/intersect_closest.cl).
//
// Rules: every test here is about what stays true at extreme scales, far
// from the origin or on degenerate input, and says in its comment what it
// checks and what it found; sizes are cut to keep the suite near two minutes
// on two cores, and each cut is said where it is made.
#pragma once

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "host/accel/bvh.h"
#include "host/accel/bvh_wide.h"
#include "host/image/image.h"
#include "host/render/device_scene.h"
#include "host/render/kernel_args.h"
#include "host/render/integrator.h"
#include "host/scene/features.h"
#include "host/scene/scene.h"
#include "tests/support/test_support.h"

namespace caustica::stiff {

// p -> scale * p + offset for everything positional: camera (position,
// look-at; focus distance and aperture scale), shapes (centres, vertices,
// radii, half lengths), lights (positions, rectangle edges, sphere radii).
// Directions, normals, materials and texture coordinates are unchanged.
// Intensities: phong's point lights have no falloff (scenes/FORMAT.md) and
// area/sphere lights and emission are radiance, so only path mode's point
// lights (radiance I / d^2) change: by scale^2 when point_light_falloff, so
// that the image is the same.
void transform_scene(Scene& s, float scale, glm::vec3 offset, bool point_light_falloff);

struct RenderResult {
  ImageF image;
  RenderStats stats;
};

// Renders `scene_path` (after `edit`, if any) at width x height on the test
// device, launching the stages in work-groups of local_size; spp only for
// path mode. Every image is checked by test::expect_finite_render.
RenderResult render(const std::string& scene_path, RenderMode mode, int width, int height,
                    const std::function<void(Scene&)>& edit = {}, int spp = 0, size_t local_size = 64);

// The official scene directory in ../shared, or the copies in scenes/.
std::string official_scene(const std::string& name);

// Closest hits of host-made rays through the real device traversal: the
// scene's BVH (built with `quality`), collapsed, uploaded, and traced by
// the renderer's intersect_closest stage, built with the scene's options
// plus extra_build_options (e.g. -cl-fast-relaxed-math).
class DeviceTracer {
 public:
  explicit DeviceTracer(const Scene& scene,
                        BvhBuildOptions::Quality quality = BvhBuildOptions::Quality::Spatial,
                        const std::string& extra_build_options = "");
  ~DeviceTracer();
  std::vector<Hit> closest(const std::vector<glm::vec3>& origin, const std::vector<glm::vec3>& dir) const;
  const Bvh& bvh() const { return bvh_; }
  const WideBvh& wide() const { return wide_; }

 private:
  const Scene& scene_;
  Bvh bvh_;
  WideBvh wide_;
  SceneFeatures features_;
  std::unique_ptr<DeviceScene> device_;
  mutable StageKernel kernel_;
};

// Fraction of pixels whose largest channel differs by more than tol.
double fraction_differing(const ImageF& a, const ImageF& b, float tol);
double mean_abs_difference(const ImageF& a, const ImageF& b);

// The scales of the kernel-level ray sets: shapes of size 1e-4, 1 and 1e4
// at the origin, and of size 1 at 1e5 from it.
struct ScaleCase {
  const char* name;
  float scale;
  glm::vec3 offset;
};
extern const ScaleCase kScaleCases[4];

// A direction uniform on the sphere.
glm::vec3 random_unit(std::mt19937& rng);

// A read-only device copy of v (one default element when v is empty, so
// that a kernel argument always has a buffer).
template <class T>
cl::Buffer upload_read_only(std::vector<T> v) {
  if (v.empty()) v.resize(1);
  return cl::Buffer(test::runtime().context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T),
                    v.data());
}

}  // namespace caustica::stiff
