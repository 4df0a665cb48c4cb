// The film: a pass in progress and the accumulated passes.
//
// Rules: stages add to the pass in progress (128-bit fixed point with 64-bit
// integer atomics, kernels/lib/film.h), one fixed point for every render
// (FILM_FRACTION_BITS), so that any value from 1e-6 to 7e16 keeps its float's
// bits in one image, whatever else the scene holds. A finished pass is added to the
// accumulated passes on the device (accumulate_film_pass.cl) as 128-bit
// integers, so sums of passes add to the same bits however they were
// grouped or wherever they were traced, and are floats only when read:
// the combined sum, and, when asked for, the sum of the passes since the
// latest power of two (the half an error estimate compares against; see
// accumulate_film_pass.cl). Every pixel counts its own samples: a wave adds
// the same count to every pixel unless it was planned with an allocation
// (adaptive sampling, host/render/adaptive_sampling.h), which the film also
// lists for the generate and shade stages (WAVE_ALLOCATION_PARAMS,
// kernels/lib/camera_sample.h); the mean of every pixel's counts stays a
// whole number of passes. Every step is
// deterministic. Nothing is cleared unless asked: a chunk that is traced
// again after a queue overflow clears only its range of the pass in
// progress, never a finished pass. NaN/Inf, negative, clamped and
// underflowing contributions are counted (FILM_COUNT_*) and reported, never hidden.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "host/image/image.h"
#include "host/render/pass_set.h"
#include "kernels/shared/types.h"

namespace caustica {

class Runtime;
struct StageKernel;
class KernelArgs;
class StageLauncher;
struct RenderStats;
class PixelShare;

struct FilmOptions {
  int width = 0, height = 0;
  bool half_buffer = false;  // keep the sum of passes [P, N) (error estimation)
  // The auxiliary passes (path mode, HAS_AUX_PASSES): albedo, shading
  // normal and depth a pixel, summed as the colour is (kernels/lib/film.h).
  bool aux_passes = false;
};

// The values a film sums per pixel: three colour channels, then, with the
// aux passes, kAuxChannels more; all of them again for the half buffer.
// Its accumulated sums are [colour of every pixel][aux of every pixel]
// [the same for the half], two 64-bit words a value.
struct FilmLayout {
  size_t pixels = 0;
  bool aux = false, half = false;
  static constexpr int kAuxChannels = 7;  // FILM_AUX_CHANNELS: albedo rgb, normal xyz, depth
  size_t values_per_pixel() const { return 3 + (aux ? kAuxChannels : 0); }
  size_t values() const { return pixels * values_per_pixel(); }  // one copy (the combined sum, or the half)
  size_t words() const { return (half ? 2 : 1) * values() * 2; }
  // The layout whose sums are `words` long, if any.
  static bool from_words(size_t pixels, size_t words, FilmLayout* layout);
};

// The aux passes as images: per-pixel sample means.
struct AuxImages {
  ImageF albedo;              // in [0, 1]
  ImageF normal;              // decoded to [-1, 1] (a mean of unit vectors: shorter where they differ)
  std::vector<float> depth;   // one a pixel: the first hit's distance along the camera ray, 0 for a miss
};

struct FilmCounts {
  uint64_t nonfinite = 0, negative = 0, clamped = 0;
  // Positive contributions below 2^-45 that rounded to 0: each lost less
  // than that (the error report weighs them against the image).
  uint64_t underflow = 0;
  uint64_t changed() const { return nonfinite + negative + clamped; }
};

// What the film holds between waves, all a render needs of it to go on
// (host/render/render_state.h writes it to a file): the accumulated sums
// (the combined sum, then the half buffer's when kept), every pixel's
// samples, half start and traced rays (adaptive sampling reads them), and
// the film's counters, and which passes it holds (absolute indices: a
// render of a subset of passes, pass_set.h). The pass in progress is empty
// between waves.
struct FilmState {
  int passes = 0;  // held.count()
  PassSet held;
  bool per_pixel = false;  // an uneven wave was accumulated (Film::uniform() is false)
  std::vector<uint32_t> spp, half_start;
  std::vector<uint64_t> pixel_rays;
  std::vector<uint64_t> accumulated;  // 128-bit sums, two words each (Film::kAccumulatedValueBytes)
  std::vector<uint32_t> counters;    // FILM_COUNTERS values
};

// An estimate kept apart from the film's passes and added to its image (the
// photon pass's caustics: SPPM's per-pixel statistics are not a mean of
// passes). It is added to mean() and to half_mean() alike, so the error
// estimate's difference of the two sees the passes' noise only.
class SeparateEstimate {
 public:
  virtual ~SeparateEstimate() = default;
  // `spp`: each pixel's samples in the film's passes.
  virtual void add_to(ImageF& image, const std::vector<uint32_t>& spp) const = 0;
  // Adds the estimate's own per-pixel expected squared error, for the error
  // estimate: its variance to `variance` and its squared bias to `bias2`
  // (same size); nothing if it has none to add.
  virtual void add_error_to(ImageF& /*variance*/, ImageF& /*bias2*/, const std::vector<uint32_t>& /*spp*/) const {}
};

// Whether the film sums of a group of processes must be added as 128-bit
// integers (a collective: every process passes whether its own need them):
// a high word, or a low word above (2^64 - 1) / processes, in any process's
// sums; otherwise their low words add exactly in 64 bits, half the bytes.
// CAUSTICA_TEST_REDUCE128 (tests only): always.
bool film_sums_need_128_bits(PixelShare& group, bool mine);
// Whether these sums (two words each, low first) need them, in a group of
// `processes`.
bool film_low_words_may_overflow(const std::vector<uint64_t>& sums128, int processes);

class Film {
 public:
  Film(Runtime& runtime, const cl::Program& program, const FilmOptions& options);
  ~Film();

  int width() const { return options_.width; }
  int height() const { return options_.height; }
  size_t pixel_count() const { return size_t(options_.width) * size_t(options_.height); }
  // Accumulated so far, in mean samples per pixel: while every pixel has
  // the same count (uniform()), the sample index of every pixel's next pass.
  int passes() const { return passes_; }
  // The passes accumulated, by absolute index: [0, passes()) unless a wave
  // was planned at another first pass (a render of a subset of passes).
  const PassSet& held() const { return held_; }
  // The absolute index of the planned wave's first pass (the sample index
  // its samples take): plan_wave's first_pass; without a plan, held().end().
  int wave_first_pass() const { return wave_first_ >= 0 ? wave_first_ : held_.end(); }
  bool has_half_buffer() const { return options_.half_buffer; }
  bool has_aux_passes() const { return options_.aux_passes; }
  FilmLayout layout() const { return FilmLayout{pixel_count(), options_.aux_passes, options_.half_buffer}; }
  // Every pixel has passes() samples (no allocation was planned yet).
  bool uniform() const { return !per_pixel_; }
  // Each pixel's samples so far (row-major).
  const std::vector<uint32_t>& pixel_spp() const { return spp_; }
  // Each pixel's samples in its half (0 where it has none yet).
  std::vector<uint32_t> half_counts() const;
  // Each pixel's samples once the planned wave is accumulated.
  std::vector<uint32_t> spp_after_wave() const;

  // FILM_PARAMS of kernels/lib/film.h: the pass in progress, for stages.
  KernelArgs& bind(KernelArgs& args) const;
  // "film_aux_offset" (the aux passes' first value in the pass), for the
  // path tracer's shade stage built with HAS_AUX_PASSES.
  KernelArgs& bind_aux(KernelArgs& args) const;

  // Before a wave of `pass_count` passes: `samples` (one count per pixel,
  // each at most kMostSamplesPerPixel, summing to pass_count x pixels) spreads
  // them unevenly; empty: pass_count for every pixel. From the first uneven
  // wave on, the film lists every wave's pixels for the stages
  // (bind_wave_allocation, wave_entries) and keeps per-pixel counts on the
  // device. `first_pass`: the wave's absolute first pass (-1: held().end());
  // waves are added in increasing pass order, an even one may not cross a
  // power of two (most_passes_from), and an uneven one (or any once the
  // film is uneven) must continue [0, passes()).
  // `traced`: the pixels [begin, end) whose samples this process traces (a
  // wave shared among processes, wave_share.h): the lists for the stages
  // hold those pixels only, while the counts (and so the sample indices and
  // the half buffer's restarts) are the whole wave's.
  void plan_wave(int pass_count, std::vector<uint32_t> samples = {}, int first_pass = -1,
                 std::pair<size_t, size_t> traced = {0, SIZE_MAX});
  // WAVE_ALLOCATION_PARAMS: the planned wave's pixels (those with samples,
  // in pixel order), their first wave sample (an exclusive prefix sum, one
  // more entry than pixels) and every pixel's samples before the wave.
  KernelArgs& bind_wave_allocation(KernelArgs& args) const;
  uint32_t wave_entries() const { return per_pixel_ ? wave_entries_ : 0u; }  // 0: every pixel alike
  // An uneven wave's listed pixels [begin, end) (plan_wave's `traced`) and
  // their samples: what the stages trace of it.
  std::pair<size_t, size_t> wave_traced_pixels() const { return traced_; }
  uint64_t wave_traced_samples() const { return traced_samples_; }
  // "pixel_rays": each pixel's count of rays traced for its samples
  // (shade_surface_path adds, per path vertex, the closest-hit ray that
  // found it and its shadow ray, when adaptive sampling weighs them), what
  // its samples cost; pixel_rays() reads it back (a blocking transfer).
  KernelArgs& bind_pixel_rays(KernelArgs& args) const;
  std::vector<uint64_t> pixel_rays() const;

  void clear();  // everything: accumulated passes, the pass in progress, counters
  // Between waves (none planned): everything the film holds (a blocking
  // read), and the film put back to it. restore throws caustica::Error when
  // the state's sizes are not this film's.
  FilmState state() const;
  void check_state(const FilmState& state) const;  // what restore checks, and nothing else
  // The checks of a state's counts against the data they describe, for a
  // film of `layout` (also `caustica merge`'s, which has no film): the
  // arrays' sizes, every pixel's samples summing to passes x pixels (each
  // equal to passes unless per-pixel), the passes listed, and nothing
  // summed in a film of no passes. Throws caustica::Error saying which.
  static void check_state_counts(const FilmState& state, const FilmLayout& layout);
  void restore(const FilmState& state);
  void clear_pass_range(size_t first_pixel, size_t pixel_count);  // of the pass in progress only
  // The planned wave is dropped unaccumulated (a time limit ran out within
  // it): the pass in progress cleared, nothing planned.
  void abandon_wave();
  // Adds the pass in progress, which holds pass_count passes (a wave, as
  // planned), to the accumulated passes and clears it. An even wave may not
  // cross the half buffer's restart at a power of two (most_passes_from).
  void accumulate_pass(StageLauncher& launcher, RenderStats* stats = nullptr, int pass_count = 1);
  // At most this many passes in one pass in progress (a wave).
  static constexpr int kMostWavePasses = 128;
  // The most samples one pixel may take in one wave (an uneven wave's cap):
  // 2^16 samples of up to 2^11 clamped contributions each fit the pass's
  // 128 bits (kernels/shared/types.h).
  static constexpr uint32_t kMostSamplesPerPixel = 65536;
  // How many passes a wave that starts after `passes` may hold: up to
  // `wanted`, kMostWavePasses and the next power of two (0 and 1: one).
  static int most_passes_from(int passes, int wanted);

  // Adds `estimate` to every image read from now on (nullptr: none).
  void set_separate_estimate(const SeparateEstimate* estimate) { separate_ = estimate; }
  ImageF mean() const;       // combined sum / passes
  // mean() (and, with_half, half_mean()) of the films of a group of
  // processes that share every wave (each counts every pixel's samples but
  // sums only its own: pass_driver.h's WaveShare): the colour sums added
  // over the group (a collective) and converted as the device converts
  // them, so the images are one process's, bit for bit, on every process.
  // The separate estimate's per-pixel state must be whole on every process.
  struct Means {
    ImageF mean, half;
  };
  Means summed_means(PixelShare& group, bool with_half) const;
  // The same for this process's band of rows (share_of(height)) only, each
  // process taking its own (a reduce-scatter: every process converts a
  // share of the image, and moves a share of the bytes): the band's mean
  // and half mean (full-size images, filled on the band's pixels [first,
  // end)) and, with_rays, its pixel_rays() summed. A collective.
  struct Band {
    size_t first = 0, end = 0;
    Means means;
    std::vector<uint64_t> rays;  // the band's pixels
  };
  Band summed_band(PixelShare& group, bool with_rays) const;
  // The passes in the half buffer while uniform(): those held from P on, P
  // the largest power of two at most the last held pass ([P, N) for passes
  // [0, N), N >= 2; PassSet::half_count). half_mean: each pixel's half's
  // mean (needs half_buffer; a pixel with an empty half gets its mean).
  int half_passes() const;
  ImageF half_mean() const;
  // The aux passes' means over every sample, and over the half's (needs
  // aux_passes; the half also half_buffer and two passes).
  AuxImages aux_mean() const;
  AuxImages aux_half_mean() const;
  // The separate estimate's per-pixel expected squared error (zero without
  // one): its variance and its squared bias, apart (the error estimate's
  // bound weighs the bias more: host/render/error_estimate.h), and their sum.
  struct SeparateError {
    ImageF variance, bias2;
    ImageF total() const;  // variance + bias2: its expected squared error
  };
  SeparateError separate_error() const;
  ImageF separate_variance() const;
  // The separate estimate alone (the photon map's caustic radiance, part of
  // mean()); nullopt without one.
  std::optional<ImageF> separate_image() const;
  FilmCounts counts() const;
  // The most light `underflow` contributions rounded to 0 could have held
  // (2^-45 each), as a share of the image's light (the accumulated sums'
  // total, plus that most).
  double underflow_share(uint64_t underflow) const;

  // The accumulated sums: 128-bit integers in the pass's fixed point, two
  // 64-bit words (low first) per channel value, so that sums of passes add
  // to the same bits however they were grouped (accumulate_film_pass.cl).
  static constexpr size_t kAccumulatedValueBytes = 2 * sizeof(uint64_t);

 private:
  // Accumulated sums and halves, in 64-bit words (two per channel value).
  size_t accumulated_words() const { return layout().words(); }
  size_t accumulated_bytes() const { return accumulated_words() * sizeof(uint64_t); }
  size_t pass_values() const { return layout().values(); }  // the pass in progress's values
  ImageF read_sums(size_t offset) const;  // the colour image's sums from `offset` (in values)
  std::vector<float> read_values(size_t offset, size_t count) const;
  AuxImages aux_from_sums(size_t offset, const std::vector<uint32_t>& counts) const;
  // The buffers the stages read from the first uneven wave on.
  void allocate_per_pixel_buffers();
  void divide_by(ImageF& image, const std::vector<uint32_t>& counts) const;
  // summed_means' and summed_band's images of pixels [first, end) from
  // their summed colour sums: `sums` holds the combined sum's values of
  // those pixels, then (with_half) the half's, `words` 64-bit words each
  // (1: the low word alone, 2: low and high). Full-size images, as mean()
  // and half_mean() on those pixels, zero elsewhere.
  Means means_of_sums(const std::vector<uint64_t>& sums, size_t words, size_t first, size_t end, bool with_half) const;

  Runtime& runtime_;
  FilmOptions options_;
  int passes_ = 0;
  PassSet held_;
  int wave_first_ = -1;  // the planned wave's first pass (-1: none planned)
  bool per_pixel_ = false;
  std::vector<uint32_t> spp_, half_start_;  // per pixel: samples, and where the half starts
  std::vector<uint32_t> wave_spp_;          // the planned wave's (empty: pass_count each)
  int planned_passes_ = 0;                   // the planned wave's pass count (0: none planned)
  uint32_t wave_entries_ = 0;
  std::pair<size_t, size_t> traced_{0, 0};  // an uneven wave's listed pixels
  uint64_t traced_samples_ = 0;             // and their samples
  cl::Buffer pixel_spp_, wave_spp_buffer_, entry_pixel_, entry_offset_;
  cl::Buffer pass_, accumulated_, counters_, pixel_rays_;
  std::unique_ptr<StageKernel> accumulate_, read_sums_, read_low_words_;
  mutable std::unique_ptr<cl::Buffer> low_words_;  // summed_band's, made at its first call
  cl::Buffer read_values_;  // read_sums' floats (one image's)
  size_t half_offset_ = FILM_PASS_ABSENT;
  const SeparateEstimate* separate_ = nullptr;
};

}  // namespace caustica
