// The photon pass of path mode (issue 13): stochastic progressive photon
// mapping for the caustic paths light -> caster+ -> receiver that path
// tracing finds badly (small lights through glass) or never (point lights).
//
// Rules: every pass emits a new batch of photons from all lights in
// proportion to power, traces them through casters with the intersect
// stage of the path tracer and its BSDF sampling, keeps those that reach a
// receiver after a caster (packed in photon order: deterministic), and
// sorts them into the device hash grid; the camera paths' later receiving
// vertices gather them inline within the pass's shared radius
// (shade_surface_path), and after the camera chunks every pixel's visible
// point (its first receiving vertex) gathers them and updates its SPPM
// statistics (kernels/photon/gather_photons.cl). Nothing crosses to the host but one
// queue count per photon bounce, the stored count and the largest radius
// (which sizes the next grid). Which paths each estimator covers:
// kernels/lib/caustics.h. A scene without casters never builds one: no
// kernels compiled, no buffers, no launches (SceneFeatures::caustics).
#pragma once

#include <CL/opencl.hpp>

#include <array>
#include <cstdint>
#include <memory>

#include "host/image/image.h"
#include "host/render/film.h"
#include "host/render/kernel_args.h"
#include "host/render/photon_grid.h"

namespace caustica {

class DeviceScene;
class StageLauncher;
struct RenderSettings;
struct RenderStats;
struct Scene;

// The largest initial gather radius when none is given: photons spread
// evenly over the scene box's surface area A would put 32 within it,
// sqrt(32 A / (pi M)) for M photons a pass, at most 0.5% of the box's
// diagonal. Each pixel starts at its footprint where that is smaller (a
// caustic stays sharp to the pixel from the first pass; SPPM keeps early
// photons in its estimate, so a large first radius blurs it for long), and
// the shared radius of later receivers starts at this one.
float default_caustic_radius(const Scene& scene, uint32_t photons_per_pass);

// Photons a pass when none are asked for: one per pixel (as pbrt-v4's SPPM),
// at least 2^14 and at most 2^20, so photon tracing costs about what the
// pass's camera paths cost whatever the image size.
uint32_t default_photons_per_pass(int width, int height);

struct PhotonPassStats {
  uint64_t emitted = 0, stored = 0;  // over the render
};

// How the photons are gathered: path mode's per-pixel SPPM statistics at
// visible points (gather_photons.cl), or phong mode's radius shared by a
// whole pass, gathered inline by its shade stage (lib/caustics.h).
enum class PhotonGather { PerPixel, SharedRadius };

class PhotonPass final : public SeparateEstimate {
 public:
  // `lights`: a PathLight table (light_count > 0): the path tracer's, or
  // phong's point lights as LIGHT_POINT entries.
  PhotonPass(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program, const cl::Buffer& lights,
             uint32_t light_count, const RenderSettings& settings, PhotonGather gather = PhotonGather::PerPixel);
  ~PhotonPass() override;

  void clear();  // a new render: radii back to the initial one, no photons
  // Before pass `pass_index`'s camera chunks: this pass's photon map.
  void trace(uint32_t pass_index, RenderStats* stats);
  // After them: every pixel gathers (PerPixel).
  void gather(uint32_t pass_index, RenderStats* stats);
  // SharedRadius: pass k's radius, r0^2 prod_{i=1..k} (i + alpha) / (i + 1)
  // squared (Knaus & Zwicker 2011), and the photon map with it:
  // PHOTON_GRID_PARAMS plus "caustic_radius".
  float shared_radius(uint32_t pass_index) const;
  KernelArgs& bind_photon_map(KernelArgs& args, uint32_t pass_index) const;
  // What shade_surface_path writes: "visible_points".
  KernelArgs& bind_visible_points(KernelArgs& args) const { return args.arg("visible_points", visible_points_); }
  // Adds the caustic radiance tau / (passes pi r^2) to the film's image.
  void add_to(ImageF& image, int passes) const override;

  const PhotonPassStats& stats() const { return stats_; }
  const PhotonGrid& grid() const { return grid_; }  // this pass's photon map

 private:
  PhotonPassParams params(uint32_t pass_index) const;

  PhotonGather gather_mode_;
  StageLauncher& launcher_;
  const DeviceScene& scene_;
  const cl::Buffer& lights_;
  uint32_t light_count_, photons_per_pass_, max_depth_, seed_;
  size_t pixel_count_;
  float initial_radius_;
  std::array<float, 3> origin_{};
  float cell_size_;
  bool fixed_radius_;  // --caustic-radius: every pixel starts at it
  int image_height_;
  StageKernel emit_, intersect_, bounce_, compact_, gather_;  // gather_: PerPixel only
  DeviceQueue queues_[2];
  cl::Buffer hits_, candidates_, stored_, offsets_, photons_, stored_count_, visible_points_, pixels_,
      largest_radius2_;
  ExclusiveScan scan_;
  PhotonGrid grid_;
  PhotonPassStats stats_;
};

}  // namespace caustica
