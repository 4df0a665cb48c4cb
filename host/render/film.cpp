#include "host/render/film.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <tuple>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"
#include "host/render/pixel_share.h"
#include "lib/film_sums.h"
#include "lib/wave_samples.h"

namespace caustica {

Film::Film(Runtime& runtime, const cl::Program& program, const FilmOptions& options)
    : runtime_(runtime), options_(options) {
  if (options.width <= 0 || options.height <= 0) throw Error("film: image size must be positive");
  const size_t values = pass_values();
  if (values > 0xFFFFFFFFull / 2) throw Error("film: image too large for 32-bit pass offsets");
  auto& ctx = runtime.context();
  pass_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, values * kAccumulatedValueBytes);
  if (options.half_buffer) half_offset_ = values;
  accumulated_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, accumulated_bytes());
  counters_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, FILM_COUNTERS * sizeof(cl_uint));
  pixel_rays_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixel_count() * sizeof(cl_ulong));
  accumulate_ = std::make_unique<StageKernel>(program, "accumulate_film_pass");
  read_sums_ = std::make_unique<StageKernel>(program, "read_film_sums");
  read_low_words_ = std::make_unique<StageKernel>(program, "read_film_low_words");
  // One image's values at a time: the colour's, or the aux passes'.
  read_values_ = cl::Buffer(ctx, CL_MEM_READ_WRITE,
                            pixel_count() * (options.aux_passes ? FilmLayout::kAuxChannels : 3) * sizeof(float));
  // Until the first uneven wave the stages read none of these.
  pixel_spp_ = wave_spp_buffer_ = entry_pixel_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  entry_offset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint));
  clear();
}

Film::~Film() = default;

KernelArgs& Film::bind(KernelArgs& args) const {
  return args.arg("film", pass_)
      .arg("film_counters", counters_)
      .arg("film_high_offset", cl_uint(pass_values()));
}

KernelArgs& Film::bind_aux(KernelArgs& args) const {
  if (!options_.aux_passes) throw Error("film: no aux passes were asked for");
  return args.arg("film_aux_offset", cl_uint(pixel_count() * 3));
}

bool FilmLayout::from_words(size_t pixels, size_t words, FilmLayout* layout) {
  for (bool aux : {false, true})
    for (bool half : {false, true}) {
      const FilmLayout l{pixels, aux, half};
      if (pixels > 0 && l.words() == words) {
        *layout = l;
        return true;
      }
    }
  return false;
}

void Film::clear() {
  runtime_.fill(pass_, cl_ulong(0), 0, pass_values() * kAccumulatedValueBytes);
  runtime_.fill(accumulated_, cl_ulong(0), 0, accumulated_bytes());
  runtime_.fill(counters_, cl_uint(0), 0, FILM_COUNTERS * sizeof(cl_uint));
  runtime_.fill(pixel_rays_, cl_ulong(0), 0, pixel_count() * sizeof(cl_ulong));
  passes_ = 0;
  held_ = PassSet();
  wave_first_ = -1;
  per_pixel_ = false;
  spp_.assign(pixel_count(), 0u);
  half_start_.assign(pixel_count(), 0u);
  wave_spp_.clear();
  planned_passes_ = 0;
  wave_entries_ = 0;
}

void Film::allocate_per_pixel_buffers() {
  auto& ctx = runtime_.context();
  const size_t pixels = pixel_count();
  pixel_spp_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_uint));
  wave_spp_buffer_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_uint));
  entry_pixel_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * sizeof(cl_uint));
  entry_offset_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, (pixels + 1) * sizeof(cl_uint));
  per_pixel_ = true;
}

FilmState Film::state() const {
  if (planned_passes_ != 0) throw Error("film: its state is taken between waves, not with a wave planned");
  FilmState s;
  s.passes = passes_;
  s.held = held_;
  s.per_pixel = per_pixel_;
  s.spp = spp_;
  s.half_start = half_start_;
  s.pixel_rays = pixel_rays();
  s.accumulated.resize(accumulated_words());
  s.counters.resize(FILM_COUNTERS);
  auto& q = runtime_.queue();
  q.enqueueReadBuffer(accumulated_, CL_TRUE, 0, s.accumulated.size() * sizeof(uint64_t), s.accumulated.data());
  q.enqueueReadBuffer(counters_, CL_TRUE, 0, s.counters.size() * sizeof(cl_uint), s.counters.data());
  return s;
}

void Film::check_state(const FilmState& s) const { check_state_counts(s, layout()); }

void Film::check_state_counts(const FilmState& s, const FilmLayout& layout) {
  const size_t pixels = layout.pixels;
  const size_t words = layout.words();
  auto wrong = [&](const std::string& what, size_t got, size_t want) {
    return Error("film: a state with " + std::to_string(got) + " " + what + " for a film of " +
                 std::to_string(want));
  };
  if (s.spp.size() != pixels) throw wrong("pixel counts", s.spp.size(), pixels);
  if (s.half_start.size() != pixels) throw wrong("half starts", s.half_start.size(), pixels);
  if (s.pixel_rays.size() != pixels) throw wrong("ray counts", s.pixel_rays.size(), pixels);
  if (s.accumulated.size() != words) throw wrong("accumulated sum words", s.accumulated.size(), words);
  if (s.counters.size() != FILM_COUNTERS) throw wrong("counters", s.counters.size(), FILM_COUNTERS);
  if (s.passes < 0) throw Error("film: a state of " + std::to_string(s.passes) + " passes");
  // The mean of the pixels' counts is the pass count (Film's rule): a state
  // that breaks it was not written by a film.
  uint64_t total = 0;
  for (uint32_t n : s.spp) total += n;
  if (total != uint64_t(s.passes) * pixels)
    throw Error("film: a state whose pixels hold " + std::to_string(total) + " samples, not " +
                std::to_string(s.passes) + " passes of " + std::to_string(pixels) + " pixels");
  if (s.held.count() != s.passes)
    throw Error("film: a state of " + std::to_string(s.passes) + " passes that lists " + s.held.describe());
  // Adaptive waves are planned from the whole film: only a film of passes
  // [0, N) has them.
  if (s.per_pixel && !s.held.is_prefix())
    throw Error("film: an adaptive (uneven) state of " + s.held.describe() + ", not of passes [0, N)");
  if (!s.per_pixel)
    for (size_t p = 0; p < pixels; ++p)
      if (s.spp[p] != uint32_t(s.passes))
        throw Error("film: an even state of " + std::to_string(s.passes) + " passes whose pixel " + std::to_string(p) +
                    " holds " + std::to_string(s.spp[p]) + " samples");
  if (s.passes == 0)
    for (uint64_t w : s.accumulated)
      if (w != 0) throw Error("film: a state of no passes that holds sums");
}

void Film::restore(const FilmState& s) {
  check_state(s);
  clear();
  auto& q = runtime_.queue();
  q.enqueueWriteBuffer(accumulated_, CL_TRUE, 0, s.accumulated.size() * sizeof(uint64_t), s.accumulated.data());
  q.enqueueWriteBuffer(counters_, CL_TRUE, 0, s.counters.size() * sizeof(cl_uint), s.counters.data());
  q.enqueueWriteBuffer(pixel_rays_, CL_TRUE, 0, s.pixel_rays.size() * sizeof(cl_ulong), s.pixel_rays.data());
  passes_ = s.passes;
  held_ = s.held;
  spp_ = s.spp;
  half_start_ = s.half_start;
  // The per-pixel buffers' contents are uploaded by every plan_wave.
  if (s.per_pixel) allocate_per_pixel_buffers();
}

void Film::plan_wave(int pass_count, std::vector<uint32_t> samples, int first_pass,
                     std::pair<size_t, size_t> traced) {
  if (pass_count < 1 || pass_count > kMostWavePasses)
    throw Error("film: a wave of " + std::to_string(pass_count) + " passes (1 to " + std::to_string(kMostWavePasses) +
                ")");
  if (first_pass < 0) first_pass = held_.end();
  if (first_pass < held_.end())
    throw Error("film: a wave at pass " + std::to_string(first_pass) + " planned after " + held_.describe() +
                " (waves are added in pass order)");
  if ((per_pixel_ || !samples.empty()) && first_pass != passes_)
    throw Error("film: an uneven wave at pass " + std::to_string(first_pass) + " after " + held_.describe() +
                " (adaptive waves continue passes [0, N))");
  planned_passes_ = pass_count;
  wave_first_ = first_pass;
  wave_spp_.clear();
  if (samples.empty() && !per_pixel_) return;
  const size_t pixels = pixel_count();
  if (samples.empty()) samples.assign(pixels, uint32_t(pass_count));
  if (samples.size() != pixels)
    throw Error("film: a wave allocation of " + std::to_string(samples.size()) + " pixels for " +
                std::to_string(pixels));
  uint64_t total = 0;
  const uint32_t most = kMostSamplesPerPixel;
  for (uint32_t k : samples) {
    if (k > most)
      throw Error("film: a pixel given " + std::to_string(k) + " samples in one wave (at most " +
                  std::to_string(most) + ")");
    total += k;
  }
  if (total != uint64_t(pass_count) * pixels || total > 0xFFFFFFFFull)
    throw Error("film: a wave allocation of " + std::to_string(total) + " samples, not " +
                std::to_string(pass_count) + " passes of " + std::to_string(pixels) + " pixels");
  if (!per_pixel_) allocate_per_pixel_buffers();
  std::vector<uint32_t> entry_pixel, entry_offset;
  entry_pixel.reserve(pixels);
  entry_offset.reserve(pixels + 1);
  traced.second = std::min(traced.second, pixels);
  traced.first = std::min(traced.first, traced.second);
  uint32_t offset = 0;
  for (size_t p = traced.first; p < traced.second; ++p) {
    if (samples[p] == 0) continue;
    entry_pixel.push_back(uint32_t(p));
    entry_offset.push_back(offset);
    offset += samples[p];
  }
  entry_offset.push_back(offset);
  wave_entries_ = uint32_t(entry_pixel.size());
  traced_ = traced;
  traced_samples_ = offset;
  auto& q = runtime_.queue();
  q.enqueueWriteBuffer(pixel_spp_, CL_TRUE, 0, pixels * sizeof(cl_uint), spp_.data());
  q.enqueueWriteBuffer(wave_spp_buffer_, CL_TRUE, 0, pixels * sizeof(cl_uint), samples.data());
  if (wave_entries_ > 0) {
    q.enqueueWriteBuffer(entry_pixel_, CL_TRUE, 0, entry_pixel.size() * sizeof(cl_uint), entry_pixel.data());
    q.enqueueWriteBuffer(entry_offset_, CL_TRUE, 0, entry_offset.size() * sizeof(cl_uint), entry_offset.data());
  }
  wave_spp_ = std::move(samples);
}

KernelArgs& Film::bind_pixel_rays(KernelArgs& args) const { return args.arg("pixel_rays", pixel_rays_); }

std::vector<uint64_t> Film::pixel_rays() const {
  std::vector<uint64_t> rays(pixel_count());
  runtime_.queue().enqueueReadBuffer(pixel_rays_, CL_TRUE, 0, rays.size() * sizeof(cl_ulong), rays.data());
  return rays;
}

KernelArgs& Film::bind_wave_allocation(KernelArgs& args) const {
  return args.arg("wave_entry_pixel", entry_pixel_).arg("wave_entry_offset", entry_offset_).arg("wave_pixel_spp",
                                                                                                 pixel_spp_);
}

std::vector<uint32_t> Film::half_counts() const {
  if (!per_pixel_) return std::vector<uint32_t>(spp_.size(), uint32_t(held_.half_count()));
  std::vector<uint32_t> h(spp_.size(), 0u);
  for (size_t p = 0; p < h.size(); ++p) h[p] = half_start_[p] > 0 ? spp_[p] - half_start_[p] : 0u;
  return h;
}

std::vector<uint32_t> Film::spp_after_wave() const {
  std::vector<uint32_t> after = spp_;
  for (size_t p = 0; p < after.size(); ++p) after[p] += wave_spp_.empty() ? uint32_t(planned_passes_) : wave_spp_[p];
  return after;
}

// The pass's low words, then its high words (kernels/lib/film.h).
// With the aux passes, their values of those pixels too.
void Film::clear_pass_range(size_t first_pixel, size_t count) {
  const size_t word = sizeof(cl_ulong), high = pass_values() * word;
  runtime_.fill(pass_, cl_ulong(0), first_pixel * 3 * word, count * 3 * word);
  runtime_.fill(pass_, cl_ulong(0), high + first_pixel * 3 * word, count * 3 * word);
  if (!options_.aux_passes) return;
  const size_t aux = pixel_count() * 3 * word, k = FilmLayout::kAuxChannels;
  runtime_.fill(pass_, cl_ulong(0), aux + first_pixel * k * word, count * k * word);
  runtime_.fill(pass_, cl_ulong(0), high + aux + first_pixel * k * word, count * k * word);
}

void Film::abandon_wave() {
  clear_pass_range(0, pixel_count());
  planned_passes_ = 0;
  wave_first_ = -1;
  wave_spp_.clear();
}

namespace {
// The half buffer's next restart after `passes`: the smallest power of two
// above it (accumulate_film_pass.cl; pass 0 is never in the half). In 64
// bits: above 2^30 passes an int's doubling overflowed, and the loop never
// ended (issue 38: --passes 2147483646:2147483647 hung).
int64_t next_half_restart(int passes) {
  int64_t p = 1;
  while (p <= passes) p *= 2;
  return p;
}
}  // namespace

void Film::accumulate_pass(StageLauncher& launcher, RenderStats* stats, int pass_count) {
  if (planned_passes_ == 0 && !per_pixel_) planned_passes_ = pass_count;  // an even wave needs no plan
  if (planned_passes_ != pass_count)
    throw Error("film: a wave of " + std::to_string(pass_count) + " passes accumulated, " +
                std::to_string(planned_passes_) + " planned");
  if (pass_count < 1 || pass_count > kMostWavePasses)
    throw Error("film: a wave of " + std::to_string(pass_count) + " passes (1 to " + std::to_string(kMostWavePasses) +
                ")");
  // While every pixel is alike the half buffer restarts at each power of
  // two: a wave may start there but not cross one.
  const int first = wave_first_pass();
  const int64_t next_restart = next_half_restart(first);
  if (!per_pixel_ && int64_t(first) + pass_count > next_restart)
    throw Error("film: a wave of passes [" + std::to_string(first) + ", " + std::to_string(int64_t(first) + pass_count) +
                ") crosses the half buffer's restart at " + std::to_string(next_restart));
  FilmAccumulate a{};
  a.value_count = cl_uint(pass_values());
  a.colour_values = cl_uint(pixel_count() * 3);
  a.half_offset = cl_uint(half_offset_);
  // The half restarts when a power of two lies in [the end of the held
  // passes, the wave's last pass]: the passes skipped (another rank's, or
  // another subset's) count as if held, so the half stays the held passes
  // from the largest power of two at most the last (PassSet::half_count).
  // For passes [0, N) this is [N, N + k): the kernel's rule as it was.
  const int from = held_.empty() ? first : held_.end();
  a.pass_index = cl_uint(from);
  a.pass_count = cl_uint(first + pass_count - from);
  a.per_pixel = per_pixel_ ? 1u : 0u;
  KernelArgs(*accumulate_)
      .arg("film", pass_)
      .arg("passes", accumulated_)
      .arg("params", a)
      .arg("pixel_spp", pixel_spp_)
      .arg("wave_spp", wave_spp_buffer_)
      .finish();
  launcher.launch(*accumulate_, a.value_count, stats);
  held_.add(first, first + pass_count);
  passes_ += pass_count;
  // Every pixel alike: the half is the held passes' (PassSet); for passes
  // [0, N) that is the per-pixel rule below.
  const int half = held_.half_count();
  for (size_t p = 0; p < spp_.size(); ++p) {
    const uint32_t n = spp_[p], k = per_pixel_ ? wave_spp_[p] : uint32_t(pass_count);
    if (per_pixel_ && film_half_restarts(n, k)) half_start_[p] = n;
    if (!per_pixel_) half_start_[p] = half > 0 ? uint32_t(passes_ - half) : 0u;
    spp_[p] = n + k;
  }
  planned_passes_ = 0;
  wave_first_ = -1;
  wave_spp_.clear();
}

int Film::most_passes_from(int passes, int wanted) {
  const int64_t room = next_half_restart(passes) - passes;
  return std::max(1, int(std::min<int64_t>({wanted, kMostWavePasses, room})));
}

std::vector<float> Film::read_values(size_t offset, size_t count) const {
  std::vector<float> values(count);
  // Converted on the device (kernels/lib/film_sums.h): a quarter of the
  // bytes cross to the host.
  KernelArgs(*read_sums_)
      .arg("passes", accumulated_)
      .arg("values", read_values_)
      .arg("value_count", cl_uint(count))
      .arg("offset", cl_uint(offset))
      .finish();
  auto& q = runtime_.queue();
  q.enqueueNDRangeKernel(read_sums_->kernel, cl::NullRange, cl::NDRange(count));
  q.enqueueReadBuffer(read_values_, CL_TRUE, 0, count * sizeof(float), values.data());
  return values;
}

ImageF Film::read_sums(size_t offset) const {
  ImageF image;
  image.width = options_.width;
  image.height = options_.height;
  image.rgb = read_values(offset, pixel_count() * 3);
  return image;
}

// The aux sums from `offset` (the combined sum's colour values, or the
// half's), each pixel divided by its count and its normal decoded.
AuxImages Film::aux_from_sums(size_t offset, const std::vector<uint32_t>& counts) const {
  if (!options_.aux_passes) throw Error("film: no aux passes were asked for");
  const size_t k = FilmLayout::kAuxChannels;
  const std::vector<float> sums = read_values(offset + pixel_count() * 3, pixel_count() * k);
  AuxImages aux;
  aux.albedo = ImageF(options_.width, options_.height);
  aux.normal = ImageF(options_.width, options_.height);
  aux.depth.assign(pixel_count(), 0.0f);
  for (size_t p = 0; p < pixel_count(); ++p) {
    const float* v = &sums[k * p];
    const float inv = counts[p] > 0 ? 1.0f / float(counts[p]) : 0.0f;
    for (int c = 0; c < 3; ++c) {
      aux.albedo.rgb[3 * p + c] = v[c] * inv;
      aux.normal.rgb[3 * p + c] = counts[p] > 0 ? 2.0f * (v[3 + c] * inv) - 1.0f : 0.0f;
    }
    aux.depth[p] = v[6] * inv;
  }
  return aux;
}

AuxImages Film::aux_mean() const { return aux_from_sums(0, spp_); }

AuxImages Film::aux_half_mean() const {
  if (!options_.half_buffer) throw Error("film: no half buffer was asked for");
  if (passes_ < 2) throw Error("film: the half buffer needs at least two passes");
  const std::vector<uint32_t> h = half_counts();
  // A pixel with no half yet: its mean (as half_mean).
  if (std::find(h.begin(), h.end(), 0u) == h.end()) return aux_from_sums(half_offset_, h);
  AuxImages half = aux_from_sums(half_offset_, h), all = aux_mean();
  for (size_t p = 0; p < h.size(); ++p) {
    if (h[p] != 0) continue;
    for (int c = 0; c < 3; ++c) {
      half.albedo.rgb[3 * p + c] = all.albedo.rgb[3 * p + c];
      half.normal.rgb[3 * p + c] = all.normal.rgb[3 * p + c];
    }
    half.depth[p] = all.depth[p];
  }
  return half;
}

// Sums to means, as value * (1 / count) (the same bits for every pixel
// alike as for one count); a pixel with no samples stays 0.
void Film::divide_by(ImageF& image, const std::vector<uint32_t>& counts) const {
  for (size_t p = 0; p < counts.size(); ++p) {
    if (counts[p] <= 1) continue;
    const float inv = 1.0f / float(counts[p]);
    for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] *= inv;
  }
}

ImageF Film::mean() const {
  ImageF image = read_sums(0);
  divide_by(image, spp_);
  if (separate_ && passes_ > 0) separate_->add_to(image, spp_);
  return image;
}

bool film_low_words_may_overflow(const std::vector<uint64_t>& sums128, int processes) {
  uint64_t high = 0, most_low = 0;
  for (size_t i = 0; i + 1 < sums128.size(); i += 2) {
    most_low = std::max(most_low, sums128[i]);
    high |= sums128[i + 1];
  }
  return high != 0 || most_low > UINT64_MAX / uint64_t(std::max(1, processes));
}

bool film_sums_need_128_bits(PixelShare& group, bool mine) {
  if (std::getenv("CAUSTICA_TEST_REDUCE128")) return true;
  std::vector<uint64_t> any = {mine ? 1u : 0u};
  group.sum_to_all(any);
  return any[0] != 0;
}

Film::Means Film::means_of_sums(const std::vector<uint64_t>& sums, size_t words, size_t first, size_t end,
                                bool with_half) const {
  const size_t n = 3 * (end - first);
  const auto image_of = [&](size_t copy) {
    ImageF image(options_.width, options_.height);
    for (size_t i = 0; i < n; ++i) {
      const size_t at = (copy * n + i) * words;
      image.rgb[3 * first + i] = film_sum_to_float(sums[at], words == 2 ? sums[at + 1] : 0u);
    }
    return image;
  };
  Means out;
  out.mean = image_of(0);
  divide_by(out.mean, spp_);  // (a pixel with an empty half takes this mean: as half_mean's)
  if (with_half) {
    const std::vector<uint32_t> h = half_counts();
    out.half = image_of(1);
    divide_by(out.half, h);
    for (size_t p = first; p < end; ++p)
      if (h[p] == 0)
        for (int c = 0; c < 3; ++c) out.half.rgb[3 * p + c] = out.mean.rgb[3 * p + c];
    if (separate_) separate_->add_to(out.half, spp_);
  }
  if (separate_ && passes_ > 0) separate_->add_to(out.mean, spp_);
  return out;
}

Film::Means Film::summed_means(PixelShare& group, bool with_half) const {
  if (with_half && !options_.half_buffer) throw Error("film: no half buffer was asked for");
  if (with_half && passes_ < 2) throw Error("film: the half buffer needs at least two passes");
  // The colour sums (the combined sum's, then the half's), two words a value.
  const size_t values = pixel_count() * 3, bytes = values * kAccumulatedValueBytes;
  std::vector<uint64_t> words(2 * values * (with_half ? 2 : 1));
  auto& q = runtime_.queue();
  q.enqueueReadBuffer(accumulated_, CL_TRUE, 0, bytes, words.data());
  if (with_half)
    q.enqueueReadBuffer(accumulated_, CL_TRUE, half_offset_ * kAccumulatedValueBytes, bytes, words.data() + 2 * values);
  if (film_sums_need_128_bits(group, film_low_words_may_overflow(words, group.size()))) {
    group.sum128_to_all(words);
    return means_of_sums(words, 2, 0, pixel_count(), with_half);
  }
  std::vector<uint64_t> low(words.size() / 2);
  for (size_t i = 0; i < low.size(); ++i) low[i] = words[2 * i];
  group.sum_to_all(low);
  return means_of_sums(low, 1, 0, pixel_count(), with_half);
}

Film::Band Film::summed_band(PixelShare& group, bool with_rays) const {
  if (!options_.half_buffer) throw Error("film: no half buffer was asked for");
  if (passes_ < 2) throw Error("film: the half buffer needs at least two passes");
  const size_t width = size_t(options_.width), values = pixel_count() * 3;
  // Each process's pixels (its rows), in rank order.
  std::vector<std::pair<size_t, size_t>> bands;
  for (int r = 0; r < group.size(); ++r) {
    const auto [y0, y1] = share_of(size_t(options_.height), r, group.size());
    bands.emplace_back(y0 * width, y1 * width);
  }
  Band out;
  std::tie(out.first, out.end) = bands[size_t(group.rank())];
  // The low words of the colour sums (the combined sum's, then the half's),
  // taken on the device with a flag for a sum they do not hold; where no
  // process's has one, the low words alone add without overflow (half the
  // bytes read and summed). CAUSTICA_TEST_REDUCE128 (tests only): never.
  auto& q = runtime_.queue();
  const size_t low_bytes = 2 * values * sizeof(cl_ulong);
  if (!low_words_ || low_words_->getInfo<CL_MEM_SIZE>() < low_bytes)
    low_words_ = std::make_unique<cl::Buffer>(runtime_.context(), CL_MEM_READ_WRITE, low_bytes);
  cl::Buffer flag(runtime_.context(), CL_MEM_READ_WRITE, sizeof(cl_uint));
  runtime_.fill(flag, cl_uint(0), 0, sizeof(cl_uint));
  for (size_t copy = 0; copy < 2; ++copy) {
    KernelArgs(*read_low_words_)
        .arg("passes", accumulated_)
        .arg("low", *low_words_)
        .arg("wide", flag)
        .arg("value_count", cl_uint(values))
        .arg("offset", cl_uint(copy == 0 ? 0 : half_offset_))
        .arg("low_offset", cl_uint(copy * values))
        .arg("most_low", cl_ulong(UINT64_MAX / uint64_t(group.size())))
        .finish();
    q.enqueueNDRangeKernel(read_low_words_->kernel, cl::NullRange, cl::NDRange(values));
  }
  cl_uint any_wide = 0;
  q.enqueueReadBuffer(flag, CL_TRUE, 0, sizeof any_wide, &any_wide);
  const bool wide = film_sums_need_128_bits(group, any_wide != 0);
  const size_t per_value = wide ? 2 : 1;
  // One segment a process, in rank order: its pixels' combined values,
  // then their half's (read straight into place); its pixels' rays.
  std::vector<uint64_t> send(2 * values * per_value);
  std::vector<size_t> counts;
  size_t at = 0;
  for (const auto& [first, end] : bands) {
    for (size_t copy = 0; copy < 2; ++copy) {
      const size_t n = 3 * (end - first);
      if (n == 0) continue;
      if (wide)
        q.enqueueReadBuffer(accumulated_, CL_FALSE, ((copy == 0 ? 0 : half_offset_) + 3 * first) * kAccumulatedValueBytes,
                            n * kAccumulatedValueBytes, send.data() + at);
      else
        q.enqueueReadBuffer(*low_words_, CL_FALSE, (copy * values + 3 * first) * sizeof(cl_ulong),
                            n * sizeof(cl_ulong), send.data() + at);
      at += n * per_value;
    }
    counts.push_back(2 * 3 * (end - first));
  }
  q.finish();
  std::vector<uint64_t> send_rays;
  std::vector<size_t> ray_counts;
  if (with_rays) {
    send_rays = pixel_rays();  // (the bands are in pixel order: already one segment a process)
    for (const auto& [first, end] : bands) ray_counts.push_back(end - first);
  }
  const std::vector<uint64_t> mine = wide ? group.sum128_scatter(send, counts) : group.sum_scatter(send, counts);
  if (with_rays) out.rays = group.sum_scatter(send_rays, ray_counts);
  out.means = means_of_sums(mine, per_value, out.first, out.end, true);
  return out;
}

int Film::half_passes() const { return held_.half_count(); }

ImageF Film::half_mean() const {
  if (!options_.half_buffer) throw Error("film: no half buffer was asked for");
  if (passes_ < 2) throw Error("film: the half buffer needs at least two passes");
  ImageF image = read_sums(half_offset_);
  const std::vector<uint32_t> h = half_counts();
  divide_by(image, h);
  // A pixel with no half yet: its mean (no difference, no estimate).
  const bool any_empty = std::find(h.begin(), h.end(), 0u) != h.end();
  const ImageF sums = any_empty ? read_sums(0) : ImageF();
  for (size_t p = 0; any_empty && p < h.size(); ++p)
    if (h[p] == 0)
      for (int c = 0; c < 3; ++c)
        image.rgb[3 * p + c] = spp_[p] > 1 ? sums.rgb[3 * p + c] * (1.0f / float(spp_[p])) : sums.rgb[3 * p + c];
  if (separate_) separate_->add_to(image, spp_);
  return image;
}

Film::SeparateError Film::separate_error() const {
  SeparateError error{ImageF(options_.width, options_.height), ImageF(options_.width, options_.height)};
  if (separate_ && passes_ > 0) separate_->add_error_to(error.variance, error.bias2, spp_);
  return error;
}

ImageF Film::SeparateError::total() const {
  ImageF sum = variance;
  for (size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += bias2.rgb[i];
  return sum;
}

ImageF Film::separate_variance() const { return separate_error().total(); }

std::optional<ImageF> Film::separate_image() const {
  if (!separate_ || passes_ == 0) return std::nullopt;
  ImageF image(options_.width, options_.height);
  separate_->add_to(image, spp_);
  return image;
}

double Film::underflow_share(uint64_t underflow) const {
  if (underflow == 0) return 0.0;
  const ImageF sums = read_sums(0);
  double total = 0.0;
  for (float v : sums.rgb) total += double(v);
  const double lost = double(underflow) * std::ldexp(1.0, -FILM_FRACTION_BITS - 1);
  return lost / (total + lost);
}

FilmCounts Film::counts() const {
  cl_uint c[FILM_COUNTERS] = {};
  runtime_.queue().enqueueReadBuffer(counters_, CL_TRUE, 0, sizeof c, c);
  FilmCounts out;
  out.nonfinite = c[FILM_COUNT_NONFINITE];
  out.negative = c[FILM_COUNT_NEGATIVE];
  out.clamped = c[FILM_COUNT_CLAMPED];
  out.underflow = c[FILM_COUNT_UNDERFLOW];
  return out;
}

}  // namespace caustica
