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
// statistics (kernels/photon/gather_photons.cl). Nothing crosses to the host but the wave
// loop's lagged non-blocking count reads (one per photon bounce), the
// stored count and the gather counters (whose radius histogram's 90th
// percentile sizes the next grid's cells). Which paths each estimator covers:
// kernels/lib/caustics.h. A scene without casters never builds one: no
// kernels compiled, no buffers, no launches (SceneFeatures::caustics).
#pragma once

#include <CL/opencl.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "host/image/image.h"
#include "host/render/film.h"
#include "host/render/device_lights.h"
#include "host/render/kernel_args.h"
#include "host/render/photon_grid.h"
#include "host/render/pixel_share.h"
#include "host/render/photon_stats.h"

namespace caustica {

class WaveLoop;
class StateReader;
class StateWriter;

class DeviceScene;
class StageLauncher;
struct RenderSettings;
struct RenderStats;
struct Scene;

// The radii follow what the camera sees, never the scene's extent (issue
// 19). A visible point starts at its camera path's footprint (the ray cone,
// shade_surface_path); a later receiver gathers within its path's footprint
// there. The first pass's grid cells are one pixel footprint at the
// camera's focus distance (its look-at point unless the file says
// otherwise); every later pass's cells are the 90th percentile of the
// visible points' radii after the previous gather (a histogram the gather
// fills on the device). No radius exceeds one cell, so a query visits at
// most 2 x 2 x 2 cells: a visible point's larger radius is reduced to that
// (tau and N scaled by the areas' ratio), and a later receiver's radius is
// also at most Knaus & Zwicker's shared radius, which starts at one
// first-pass cell and shrinks as r^2 prod (i + alpha) / (i + 1).
float camera_footprint_at_focus(const Scene& scene, int image_height);

// Guided emission (kernels/photon/emit_photons.cl): a bounding sphere (xyz
// centre, w radius) per caster object: each caster sphere and cylinder, and
// the box of each caster material's triangles. Empty (emission unguided)
// when there are more than 64 or any is not finite.
std::vector<cs_float4> caster_bounds(const Scene& scene);

// Photons a pass when none are asked for: one per pixel (as pbrt-v4's SPPM),
// at least 2^14 and at most 2^20, so photon tracing costs about what the
// pass's camera paths cost whatever the image size.
uint32_t default_photons_per_pass(int width, int height);

struct PhotonPassStats {
  uint64_t emitted = 0, stored = 0, photon_rays = 0;  // over the render
  double seconds = 0.0;  // host wall time in trace and gather (both end in a blocking read)
  PhotonGatherStats gathers;
};

// How the photons are gathered: path mode's per-pixel SPPM statistics at
// visible points (gather_photons.cl), or phong mode's radius shared by a
// whole pass, gathered inline by its shade stage (lib/caustics.h).
enum class PhotonGather { PerPixel, SharedRadius };

class PhotonPass final : public SeparateEstimate {
 public:
  // `lights`: a light table (at least one light): the path tracer's, or
  // phong's delta lights and environment (phong_photon_lights,
  // host/lights/light_table.h).
  PhotonPass(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program, const DeviceLights& lights,
             const RenderSettings& settings, PhotonGather gather = PhotonGather::PerPixel);
  ~PhotonPass() override;

  void clear();  // a new render: radii back to the initial one, no photons
  // A render shared by pixels among processes (pixel_share.h; PerPixel
  // only): from now on this process traces its slice of each map's
  // photons, gathers every process's stored photons in rank order (photon
  // order: the map one process would build) and updates the SPPM
  // statistics of its window of pixels only; the gather counters (the
  // radius histogram the next cells follow) are summed over the processes.
  // `share` outlives the pass.
  void share(PixelShare* share);
  std::pair<size_t, size_t> pixel_window() const { return {first_pixel_, pixel_end_}; }
  // The SPPM statistics of this process's window, and with `whole_state`
  // its visible points and gather counters too (only a state file needs
  // them: the image and its error estimate read the statistics), as bytes;
  // and (rank 0) putting every other process's into its own buffers
  // (before save() or add_to: the whole image's; the others' counters are
  // added in save() only, since this process's own go on counting).
  // Between waves.
  std::string pixel_slice(bool whole_state) const;
  void put_pixel_slices(const std::vector<std::string>& by_rank);
  // `auto`'s decisions, shared by pixels (collective): every process's
  // window of statistics into every process's buffers (the films' means
  // come whole from Film::summed_means). One process: nothing to do.
  void gather_pixels_to_all();
  // A process other than rank 0 resuming a state: its gather counters
  // start at zero (rank 0's hold the state's).
  void zero_counters();
  // Render state files (host/render/render_state.h), between waves: the
  // schedule (maps, gathers, on or off, the cells), every pixel's SPPM
  // statistics and visible point, the gather counters of the passes since
  // the latest map, and that map's photons (load builds its grid again:
  // the same photons and cells give the same grid).
  void save(StateWriter& out) const;
  void load(StateReader& in);
  // A new photon map (the next photon pass; in path mode `auto` may trace
  // one every few camera passes, integrator_path.cpp), before a camera
  // pass's chunks.
  void trace(RenderStats* stats);
  // SharedRadius (phong: a map every pass): map `map_index`, the absolute
  // pass index, whose radius and random numbers are the same however the
  // passes are split (MPI ranks trace interleaved passes).
  void trace_map(uint32_t map_index, RenderStats* stats) {
    maps_ = map_index;
    trace(stats);
  }
  // After that pass's chunks: every pixel gathers the map (PerPixel).
  void gather(RenderStats* stats);
  uint32_t photon_passes() const { return maps_; }
  // SharedRadius: photon pass k's radius, r0^2 prod_{i=1..k} (i + alpha) /
  // (i + 1) squared (Knaus & Zwicker 2011), and the latest photon map with
  // it: PHOTON_GRID_PARAMS plus "caustic_radius".
  float shared_radius(uint32_t map_index) const;
  // PerPixel: the largest radius of a later receiver's inline gather, 0
  // when the pass is off (the shade stage then leaves out every photon-map
  // step and counts every path itself).
  float later_receiver_radius() const;
  KernelArgs& bind_photon_map(KernelArgs& args) const;
  // Reads the gather counters into the stats and zeroes them (the gather
  // does it after every map; the integrator once more at the end).
  void read_counters(RenderStats* stats);
  // `auto` (issue 19): the photon pass turned off for the rest of a render
  // (what it gathered stays in the image); `spp_while_on`: each pixel's
  // samples so far, the current wave's included (those left the caustic
  // paths to the map).
  void turn_off(std::vector<uint32_t> spp_while_on) {
    on_ = false;
    spp_while_on_ = std::move(spp_while_on);
  }
  bool on() const { return on_; }
  uint32_t photons_per_pass() const { return photons_per_pass_; }
  const PhotonGatherStats& last_pass_gathers() const { return last_gathers_; }
  uint64_t last_pass_photon_rays() const { return last_photon_rays_; }
  uint64_t last_pass_stored() const { return last_stored_; }
  // The caustic radiance image's sum over pixels and channels (add_to's
  // terms), reading the pixels back.
  double caustic_total(const std::vector<uint32_t>& spp) const;
  // Adds each pixel's expected squared error of the caustic radiance to
  // `variance`. Noise: a map's own estimate L_k = beta sum_k / (pi r_k^2)
  // has variance about c / r_k^2 (its photons go as r_k^2); c = (sum L_k^2
  // r_k^2 - Lbar^2 sum r_k^2) / (n - 1) over n maps, and the pixel's
  // estimate, a mean of n maps at its current radius r, has c / (n r^2);
  // at least L^2 / N, a density estimate's Poisson noise for the N photons
  // it holds (the one figure a single map gives: before issue 45 a render
  // of one map reported no photon-map error at all).
  // Bias: (r / r_0)^2 / 8 times the caustic image's Laplacian (a disk's
  // average of L is L + r^2 lap L / 8; r_0, one footprint, is about a
  // pixel), squared, less the Laplacian's own noise (the noise alone: a
  // pixel's squared bias is kept apart from what its neighbours read).
  // Times add_to's share squared. On scenes/caustics.json this keeps the caustic region's
  // estimate within 0.8-1.6x of the true relMSE from 16 to 256 passes
  // (tests/test_caustics_error.cpp); without it, 0.1-0.2x.
  void add_error_to(ImageF& variance, ImageF& bias2, const std::vector<uint32_t>& spp) const override;
  // What shade_surface_path writes: "visible_points".
  KernelArgs& bind_visible_points(KernelArgs& args) const { return args.arg("visible_points", visible_points_); }
  // Adds the caustic radiance to the film's image: tau / (maps pi r^2), the
  // mean over the photon maps, times the share of the pixel's samples that
  // left the caustic paths to it (all of them unless `auto` turned it off).
  void add_to(ImageF& image, const std::vector<uint32_t>& spp) const override;

  const PhotonPassStats& stats() const { return stats_; }
  // Shared by pixels: what gathering the maps cost so far (pixel_share.h).
  SharedPhotonTraffic traffic() const { return traffic_; }
  const PhotonGrid& grid() const { return grid_; }  // this pass's photon map

 private:
  PhotonPassParams params(uint32_t map_index) const;
  // add_to's factor for pixel p: its samples that left the caustic to the map
  double film_share(size_t p, const std::vector<uint32_t>& spp) const;

  std::vector<SppmPixel> read_pixels() const;
  // read_counters, the gather's: summed over the processes first when shared.
  void read_counters(RenderStats* stats, bool summed);
  // Shared: every process's stored photons of this map into photons_ and
  // stored_count_, in rank order.
  void exchange_photons(RenderStats* stats);

  PhotonGather gather_mode_;
  StageLauncher& launcher_;
  const DeviceScene& scene_;
  const DeviceLights& lights_;
  uint32_t light_count_, photons_per_pass_, max_depth_, seed_, caster_count_ = 0;
  size_t pixel_count_;
  PixelShare* share_ = nullptr;  // shared by pixels among processes; nullptr: one process
  size_t first_pixel_ = 0, pixel_end_ = 0;  // this process's pixels (all of them in one)
  uint32_t first_photon_ = 0, photon_end_ = 0;  // its photons of each map (all of them in one)
  float first_cell_size_;  // the first pass's cells
  std::array<float, 3> origin_{};
  float cell_size_;
  float map_cell_size_ = 0.0f;  // the latest map's cells (cell_size_ is the next's)
  bool fixed_radius_;  // --caustic-radius: every pixel starts at it
  bool on_ = true;
  uint32_t maps_ = 0, gathered_ = 0;
  std::vector<uint32_t> spp_while_on_;  // after turn_off: each pixel's samples while on
  std::array<uint64_t, PHOTON_RADIUS_BINS> radii_{};  // the latest gather's radius histogram
  PhotonGatherStats last_gathers_;
  uint64_t last_photon_rays_ = 0, last_stored_ = 0;
  StageKernel emit_, intersect_, bounce_, compact_, gather_;  // gather_: PerPixel only
  // The paths shape (settings.kernel_shape, trace_photons.cl): one kernel
  // per map; progress_: photons taken, rays traced.
  bool paths_shape_ = false;
  void trace_wavefront(const PhotonPassParams& p, RenderStats* stats);
  void trace_paths(const PhotonPassParams& p, RenderStats* stats);
  StageKernel trace_;
  cl::Buffer progress_;
  DeviceQueue queues_[2];
  std::unique_ptr<WaveLoop> loop_;  // the bounce loop (host/render/wave_loop.h)
  cl_uint photon_rays_seen_ = 0;    // its photon-ray counter after the latest map
  cl::Buffer casters_;
  cl::Buffer hits_, candidates_, stored_, offsets_, photons_, stored_count_, visible_points_, pixels_,
      gather_counters_;
  ExclusiveScan scan_;
  PhotonGrid grid_;
  PhotonPassStats stats_;
  SharedPhotonTraffic traffic_;  // shared by pixels: the maps' gathers, over the render
  std::vector<uint64_t> others_counters_;  // rank 0: the other processes' gather counters (put_pixel_slices)
};

}  // namespace caustica
