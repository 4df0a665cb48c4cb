#include "host/render/film.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

namespace caustica {

FilmParams film_params_for_bound(float pass_bound) {
  FilmParams p{};
  const double bound = std::isfinite(pass_bound) && pass_bound > 0.0f ? double(pass_bound) : 1.0;
  // scale * bound <= 2^56, at most 2^24; one contribution may be up to
  // 2^56 / scale (>= bound), so even 256 clamped ones cannot overflow 2^64.
  const int exponent = std::min(24, int(std::floor(56.0 - std::log2(bound))));
  p.scale = std::ldexp(1.0f, exponent);
  p.max_contribution = float(std::ldexp(1.0, 56 - exponent));
  return p;
}

Film::Film(Runtime& runtime, const cl::Program& program, const FilmOptions& options)
    : runtime_(runtime), options_(options), params_(film_params_for_bound(options.pass_bound)) {
  if (options.width <= 0 || options.height <= 0) throw Error("film: image size must be positive");
  const size_t values = pixel_count() * 3;
  if (values > 0xFFFFFFFFull / 2) throw Error("film: image too large for 32-bit pass offsets");
  auto& ctx = runtime.context();
  pass_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, values * sizeof(cl_ulong));
  const size_t float_passes = options.half_buffer ? 2 : 1;
  if (options.half_buffer) half_offset_ = values;
  accumulated_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, float_passes * values * sizeof(float));
  counters_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, FILM_COUNTERS * sizeof(cl_uint));
  accumulate_ = std::make_unique<StageKernel>(program, "accumulate_film_pass");
  clear();
}

Film::~Film() = default;

KernelArgs& Film::bind(KernelArgs& args) const {
  return args.arg("film", pass_).arg("film_counters", counters_).arg("film_params", params_);
}

void Film::clear() {
  runtime_.fill(pass_, cl_ulong(0), 0, pixel_count() * 3 * sizeof(cl_ulong));
  runtime_.fill(accumulated_, 0.0f, 0, (options_.half_buffer ? 2 : 1) * pixel_count() * 3 * sizeof(float));
  runtime_.fill(counters_, cl_uint(0), 0, FILM_COUNTERS * sizeof(cl_uint));
  passes_ = 0;
}

void Film::clear_pass_range(size_t first_pixel, size_t count) {
  runtime_.fill(pass_, cl_ulong(0), first_pixel * 3 * sizeof(cl_ulong), count * 3 * sizeof(cl_ulong));
}

namespace {
// The half buffer's next restart after `passes`: the smallest power of two
// above it (accumulate_film_pass.cl; pass 0 is never in the half).
int next_half_restart(int passes) {
  int p = 1;
  while (p <= passes) p *= 2;
  return p;
}
}  // namespace

void Film::accumulate_pass(StageLauncher& launcher, RenderStats* stats, int pass_count) {
  if (pass_count < 1 || pass_count > kMostWavePasses)
    throw Error("film: a wave of " + std::to_string(pass_count) + " passes (1 to " + std::to_string(kMostWavePasses) +
                ")");
  // The half buffer restarts at each power of two: a wave may start there
  // but not cross one.
  const int next_restart = next_half_restart(passes_);
  if (passes_ + pass_count > next_restart)
    throw Error("film: a wave of passes [" + std::to_string(passes_) + ", " + std::to_string(passes_ + pass_count) +
                ") crosses the half buffer's restart at " + std::to_string(next_restart));
  FilmAccumulate a{};
  a.value_count = cl_uint(pixel_count() * 3);
  a.half_offset = cl_uint(half_offset_);
  a.pass_index = cl_uint(passes_);
  a.inv_scale = 1.0f / params_.scale;
  a.pass_count = cl_uint(pass_count);
  KernelArgs(*accumulate_).arg("film", pass_).arg("passes", accumulated_).arg("params", a).finish();
  passes_ += pass_count;
  launcher.launch(*accumulate_, a.value_count, stats);
}

int Film::most_passes_from(int passes, int wanted) {
  const int next_restart = next_half_restart(passes);
  return std::max(1, std::min({wanted, kMostWavePasses, next_restart - passes}));
}

ImageF Film::read_pass(size_t offset, int passes) const {
  ImageF image;
  image.width = options_.width;
  image.height = options_.height;
  image.rgb.resize(pixel_count() * 3);
  runtime_.queue().enqueueReadBuffer(accumulated_, CL_TRUE, offset * sizeof(float), image.rgb.size() * sizeof(float),
                                     image.rgb.data());
  if (passes > 1) {
    const float inv = 1.0f / float(passes);
    for (float& v : image.rgb) v *= inv;
  }
  return image;
}

ImageF Film::mean() const {
  ImageF image = read_pass(0, passes_);
  if (separate_ && passes_ > 0) separate_->add_to(image, passes_);
  return image;
}

int Film::half_passes() const {
  if (passes_ < 2) return 0;
  int first = 1;
  while (first <= (passes_ - 1) / 2) first *= 2;
  return passes_ - first;
}

ImageF Film::half_mean() const {
  if (!options_.half_buffer) throw Error("film: no half buffer was asked for");
  if (passes_ < 2) throw Error("film: the half buffer needs at least two passes");
  ImageF image = read_pass(half_offset_, half_passes());
  if (separate_) separate_->add_to(image, passes_);
  return image;
}

ImageF Film::separate_variance() const {
  ImageF variance(options_.width, options_.height);
  if (separate_ && passes_ > 0) separate_->add_variance_to(variance, passes_);
  return variance;
}

FilmCounts Film::counts() const {
  cl_uint c[FILM_COUNTERS] = {};
  runtime_.queue().enqueueReadBuffer(counters_, CL_TRUE, 0, sizeof c, c);
  FilmCounts out;
  out.nonfinite = c[FILM_COUNT_NONFINITE];
  out.negative = c[FILM_COUNT_NEGATIVE];
  out.clamped = c[FILM_COUNT_CLAMPED];
  return out;
}

}  // namespace caustica
