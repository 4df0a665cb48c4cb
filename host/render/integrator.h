// An integrator: one render mode, owning its stages, queues and lights.
//
// Rules: an integrator traces a wave of samples (one pass, or several where
// it says so: wave_passes) of a chunk of pixels into the film's pass in
// progress and nothing else; the pass driver
// (host/render/pass_driver.h) decides chunks, retries, passes and when to
// stop, and the film keeps what finished passes added. An integrator builds
// from its own program (kernels/integrator_<mode>.cl: only its stages, one
// program per integrator and feature set). A new mode is a new
// integrator_<mode>.{cpp,cl} pair, its make_<mode>_integrator and one case
// in make_integrator and integrator_program_file.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/error.h"
#include "host/lights/light_tree.h"
#include "host/render/adaptive_sampling.h"
#include "host/render/film.h"
#include "host/render/photon_stats.h"
#include "host/render/pixel_share.h"
#include "host/scene/scene.h"

namespace caustica {

class DeviceScene;
class DeviceQueue;
class Runtime;
struct StageKernel;

// --kernel-shape: Wavefront, Paths, or (Auto) paths on CPU devices and the
// wavefront elsewhere; prepare_session resolves Auto.
enum class KernelShape { Auto, Wavefront, Paths };
KernelShape parse_kernel_shape(const std::string& name);  // auto | wavefront | paths
const char* kernel_shape_name(KernelShape shape);

struct RenderSettings {
  int width = 0;  // image size (already resolved from the camera and CLI)
  int height = 0;
  size_t local_size = 64;         // work-group size of every stage launch
  size_t chunk_pixels = 1 << 19;  // pixels per wavefront; bounds queue memory
  float min_weight = 1e-4f;       // phong: secondary rays below this weight are not traced
  // Phong: ray queue capacity = factor x chunk. 2 holds any single wave;
  // deeper Fresnel trees overflow and their chunk is traced again in halves.
  float queue_capacity_factor = 2.0f;
  int passes = 1;            // samples per pixel (one pass each): the render's passes end here
  int first_pass = 0;        // ... and begin here (absolute indices: a render of passes [first_pass, passes))
  double time_limit_s = 0.0;  // stop after the pass that reaches this wall time; 0: none
  bool half_buffer = false;  // film keeps the half buffer: passes [P, N), P the last power of two
  // Path: adaptive sampling (host/render/adaptive_sampling.h; the film then
  // keeps its half buffer whatever half_buffer says).
  bool adaptive = false;
  AdaptiveOptions adaptive_options;
  uint32_t seed = 0;         // path: the sample sequences' seed (same seed, same image)
  uint32_t path_strategy = PATH_STRATEGY_MIS;  // path: MIS, or one technique alone (tests)
  uint32_t sampler = SAMPLER_SOBOL_BURLEY;     // path: low-discrepancy or independent samples
  // Path: the photon pass for caustics (host/render/photon_pass.h); the
  // program must have been built with it (SceneFeatures::caustics).
  bool caustics = false;
  // --caustics auto: the pass measures its work and what it brings after
  // its first passes and picks a photon-map interval or turns itself off
  // (integrator_path.cpp, decide_photon_pass).
  bool caustics_auto = false;
  // Photons emitted toward the casters' bounding spheres (emit_photons.cl);
  // off: every light's full distribution (tests compare the two).
  bool photon_guiding = true;
  uint32_t photons_per_pass = 0;  // 0: default_photons_per_pass
  float caustic_radius = 0.0f;  // every pixel's initial gather radius; 0: its footprint
  bool check_numerics = false;  // path: BSDF weight counters (program built with -DHAS_NUMERIC_CHECKS=1)
  // Path: the film's albedo, normal and depth passes (program built with
  // -DHAS_AUX_PASSES=1; host/render/film.h).
  bool aux_passes = false;
  // Path: how the stages run (issue 39): as a wavefront of kernels over
  // queues, or whole paths per work-item in one kernel (the CPU's shape).
  // The same bits either way.
  KernelShape kernel_shape = KernelShape::Wavefront;
  // Path: how next-event estimation picks a light (host/lights/light_tree.h;
  // resolved by the session: Tree and Uniform need a program built with
  // -DHAS_LIGHT_TREE=1). The photon pass emits by power whatever it says.
  LightSampler light_sampler = LightSampler::Power;
};

struct RenderStats {
  double render_ms = 0.0;
  int passes = 0;
  uint64_t camera_rays = 0;
  uint64_t secondary_rays = 0;
  uint64_t photon_rays = 0;  // photon pass: photon path segments traced
  // --check-numerics: NUMERICS_COUNTERS values (kernels/shared/types.h).
  std::vector<uint64_t> numerics;
  uint64_t shadow_rays = 0;   // traced: slots holding a ray (counted per work-group on the device)
  uint64_t shadow_slots = 0;  // addressed shadow slots, traced or empty
  int chunk_retries = 0;  // chunks traced again in halves after a queue overflow
  // Host traffic: kernel launches and blocking reads/writes (queue counts),
  // and the wave loop's count reads: non-blocking, each waited for only
  // after the next iterations are queued behind it, so the device never
  // idles for them (host/render/wave_loop.h; path, phong, photon pass).
  uint64_t launches = 0;
  uint64_t blocking_transfers = 0;
  uint64_t count_reads = 0;
  FilmCounts film;  // contributions dropped or clamped
  // Device time per stage kernel, ms (only on a profiling runtime).
  std::map<std::string, double> stage_ms;
  // The photon pass (path mode with caustics): what its gathers read, its
  // photons per pass at the end, how many it stored, and what `auto`
  // decided and why (empty when it decided nothing).
  PhotonGatherStats photon_gathers;
  uint32_t photons_per_pass = 0;
  uint64_t photons_stored = 0;
  double photon_seconds = 0.0;  // host wall time tracing and gathering photon maps (not the inline gathers)
  uint32_t photon_maps = 0;     // photon maps traced
  std::string caustics_decision;
  uint64_t rays() const { return camera_rays + secondary_rays + shadow_rays + photon_rays; }
};

// Every stage launch and queue-count transfer of a render goes through one
// launcher, which counts them into RenderStats and, on a profiling runtime,
// keeps each launch's event to sum device time per stage (collect).
class StageLauncher {
 public:
  StageLauncher(Runtime& runtime, size_t local_size) : runtime_(runtime), local_size_(local_size) {}
  // `count` work-items, padded to the local size (PoCL picks local size 1
  // for awkward global sizes); nothing for 0.
  void launch(StageKernel& stage, size_t count, RenderStats* stats);
  uint32_t read_count(const cl::Buffer& counter, RenderStats* stats);
  void write_count(const cl::Buffer& counter, uint32_t value, RenderStats* stats);
  // A non-blocking read of `bytes` from `buffer` into `destination`, done
  // when `done` completes (a count read).
  void read_async(const cl::Buffer& buffer, size_t bytes, void* destination, cl::Event* done, RenderStats* stats);
  // Adds the device time of the launches since the last collect to
  // stats->stage_ms (waits for them).
  void collect(RenderStats* stats);
  Runtime& runtime() { return runtime_; }
  size_t local_size() const { return local_size_; }

 private:
  Runtime& runtime_;
  size_t local_size_;
  std::vector<std::pair<std::string, cl::Event>> events_;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // `passes` samples (passes film.passes() on) for pixels [first_pixel,
  // first_pixel + pixel_count) into the film's pass in progress. False when
  // a queue overflowed: the driver then clears that range of the pass and
  // traces it again in halves.
  virtual bool trace_chunk(Film& film, size_t first_pixel, size_t pixel_count, int passes, RenderStats* stats) = 0;
  // The most passes the next wave may trace at once (the driver caps it
  // further: the passes asked for, the time limit, the film's rules). It
  // depends on the film's pass count and the image only, never on timing,
  // so that a render's waves, and so its bits, are the same on any machine.
  virtual int wave_passes(const Film& /*film*/) const { return 1; }
  // Around each wave's chunks: work that spans the whole image (the photon
  // pass traces its photons before and gathers after); `passes` is the
  // wave's.
  virtual void begin_pass(Film& /*film*/, RenderStats* /*stats*/) {}
  virtual void end_pass(Film& /*film*/, int /*passes*/, RenderStats* /*stats*/) {}
  // Adaptive sampling (host/render/adaptive_sampling.h): may the next wave
  // give pixels different sample counts? Only path mode's waves may, and
  // not those that trace a photon map.
  virtual bool wave_may_be_uneven(const Film& /*film*/) const { return false; }
  // What kind of pass comes next, for the driver's time prediction (passes
  // of one kind take about as long): path mode's passes that trace a photon
  // map are 1, the others 0.
  virtual int next_pass_kind(const Film& /*film*/) const { return 0; }
  // After a wave of `wave` passes now, the next wave that may be uneven as
  // the state now predicts it: the one-pass uniform waves before it (path
  // mode's photon-map passes) and its most passes (0: none). Adaptive
  // sampling places that wave ahead (PassDriver); a wrong guess costs only
  // the work.
  struct UnevenWaveGuess {
    int uniform_passes = 0;
    int passes = 0;
  };
  virtual UnevenWaveGuess next_uneven_wave(const Film& /*film*/, int /*wave*/) const { return {}; }
  // After the last pass: whatever the integrator counted on the device.
  virtual void collect(RenderStats* /*stats*/) {}
  // Render state files (host/render/render_state.h): what later waves
  // depend on beyond the film, between waves (the photon pass's statistics,
  // latest map and schedule), as bytes; empty: nothing. restore_state puts
  // it back after the film was restored (`what` names the file in errors).
  virtual std::string state() const { return {}; }
  virtual void restore_state(Film& /*film*/, const std::string& bytes, const std::string& what) {
    if (!bytes.empty()) throw Error(what + ": integrator state for a " + name_ + " render that keeps none");
  }

  // A render whose waves are shared among processes (pass_driver.h's
  // WaveShare; host/render/pixel_share.h): true when this integrator takes
  // part (path mode: every wave's samples split, and with the photon pass
  // its share of each photon map and its window's statistics only); false:
  // the processes split passes instead (binary and phong's one pass).
  virtual bool share_pixels(PixelShare* /*share*/) { return false; }
  // Shared by pixels, between waves: this process's per-pixel state of its
  // window as bytes (`for_state`: all of it; else what the image and its
  // error estimate need), and (rank 0) every other process's put into its
  // own, so that state() is the whole image's.
  virtual std::string pixel_slice(bool /*for_state*/) const { return {}; }
  virtual void put_pixel_slices(const std::vector<std::string>& /*by_rank*/) {}
  // Shared by pixels, a process other than rank 0 resuming a state: zero
  // the sums the processes keep apart (its film's are zeroed by the
  // caller; the photon pass's gather counters here).
  virtual void zero_shared_sums() {}
  // Shared, between waves (collective): every process's window of the
  // per-pixel state the image reads beyond the film (the photon pass's
  // statistics) into every process's, so that the whole image can be
  // formed on each (Film::summed_means).
  virtual void gather_shared_pixels() {}
  // Shared by pixels: what gathering the photon maps cost this process.
  virtual SharedPhotonTraffic shared_photon_traffic() const { return {}; }

  const char* name() const { return name_; }  // the mode, as --mode spells it
  // Pixels per chunk its queues are sized for.
  size_t chunk_pixels() const { return chunk_pixels_; }

 protected:
  Integrator(const char* name, StageLauncher& launcher, const DeviceScene& scene, const RenderSettings& settings)
      : launcher_(launcher), scene_(scene), settings_(settings), name_(name) {}
  // The camera restricted to pixels [first_pixel, first_pixel + pixel_count).
  CameraGPU chunk_camera(size_t first_pixel, size_t pixel_count) const;
  // generate_camera_rays for a chunk into `rays`, whose count (`count`) it
  // sets to one ray a pixel; it also zeroes `next_count`.
  void generate_camera_rays(StageKernel& generate, const DeviceQueue& rays, const cl::Buffer& count,
                            const cl::Buffer& next_count, size_t first_pixel, size_t pixel_count, RenderStats* stats);

  StageLauncher& launcher_;
  const DeviceScene& scene_;
  RenderSettings settings_;
  size_t chunk_pixels_ = 0;  // set by the constructors

 private:
  const char* name_;
};

// The kernel program of a mode ("integrator_phong.cl"); throws
// caustica::Error for a mode that is not built yet.
std::string integrator_program_file(RenderMode mode);

std::unique_ptr<Integrator> make_integrator(RenderMode mode, StageLauncher& launcher, const DeviceScene& scene,
                                            const cl::Program& program, const RenderSettings& settings);

// One per integrator_<mode>.cpp (the classes stay in their files).
std::unique_ptr<Integrator> make_binary_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                   const cl::Program& program, const RenderSettings& settings);
std::unique_ptr<Integrator> make_phong_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                  const cl::Program& program, const RenderSettings& settings);
std::unique_ptr<Integrator> make_path_integrator(StageLauncher& launcher, const DeviceScene& scene,
                                                 const cl::Program& program, const RenderSettings& settings);

}  // namespace caustica
