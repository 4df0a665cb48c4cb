#include "host/render/photon_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "host/cl/runtime.h"
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/state_bytes.h"
#include "host/render/wave_loop.h"
#include "host/scene/features.h"
#include "host/scene/scene.h"

namespace caustica {
namespace {

constexpr float kSppmAlpha = 2.0f / 3.0f;  // Hachisuka & Jensen's choice (the issue's)

// The next pass's cells: the radius below which this share of the visible
// points' radii lie (their histogram in quarter octaves).
constexpr double kCellQuantile = 0.9;

// Guided emission (emit_photons.cl) loops over every bound per photon.
constexpr size_t kMostCasterBounds = 64;

}  // namespace

std::vector<cs_float4> caster_bounds(const Scene& scene) {
  std::vector<cs_float4> bounds;
  auto casts = [&](uint32_t material) {
    return material < scene.materials.size() && material_casts_caustics(scene, scene.materials[material]);
  };
  for (const Sphere& s : scene.spheres)
    if (casts(s.material)) bounds.push_back(s.center_radius);
  for (const Cylinder& c : scene.cylinders)
    if (casts(c.material)) {
      const float r = c.center_radius.w, h = c.axis_half.w;
      bounds.push_back(cs_float4{c.center_radius.x, c.center_radius.y, c.center_radius.z, std::sqrt(r * r + h * h)});
    }
  // Triangles: one box per material (a mesh, or the faces of one object).
  std::map<uint32_t, std::pair<glm::vec3, glm::vec3>> boxes;
  for (const Triangle& t : scene.triangles) {
    if (!casts(t.material)) continue;
    auto [it, fresh] = boxes.try_emplace(t.material, glm::vec3(INFINITY), glm::vec3(-INFINITY));
    for (const cs_float4& v : {t.v0, t.v1, t.v2}) {
      it->second.first = glm::min(it->second.first, to_vec3(v));
      it->second.second = glm::max(it->second.second, to_vec3(v));
    }
  }
  for (const auto& [material, box] : boxes) {
    const glm::vec3 centre = 0.5f * (box.first + box.second);
    // a hair wider than the box's half diagonal: the cone test runs in floats
    const float r = 0.5f * glm::length(box.second - box.first) * (1.0f + 1e-5f);
    bounds.push_back(cs_float4{centre.x, centre.y, centre.z, r});
  }
  for (const cs_float4& b : bounds)
    if (!(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z) && std::isfinite(b.w) && b.w > 0.0f))
      return {};
  if (bounds.size() > kMostCasterBounds) return {};
  return bounds;
}

float camera_footprint_at_focus(const Scene& scene, int image_height) {
  const CameraDesc& cam = scene.camera;
  const float pixel_angle = 2.0f * std::tan(glm::radians(cam.fov_y_degrees) * 0.5f) / float(std::max(1, image_height));
  float distance = cam.focus_distance > 0.0f ? cam.focus_distance : glm::length(cam.look_at - cam.position);
  if (!(distance > 0.0f) || !std::isfinite(distance)) distance = 1.0f;
  const float r = PHOTON_RADIUS_FOOTPRINTS * pixel_angle * distance;
  return r > 0.0f && std::isfinite(r) ? r : 1e-3f;
}

void PhotonGatherStats::add(const PhotonGatherStats& o) {
  gathers_d1 += o.gathers_d1;
  visits_d1 += o.visits_d1;
  gathers_later += o.gathers_later;
  visits_later += o.visits_later;
  for (size_t i = 0; i < histogram_d1.size(); ++i) {
    histogram_d1[i] += o.histogram_d1[i];
    histogram_later[i] += o.histogram_later[i];
  }
}

double PhotonGatherStats::quantile(const std::array<uint64_t, PHOTON_VISIT_BINS>& h, double q) {
  uint64_t total = 0;
  for (uint64_t c : h) total += c;
  if (total == 0) return 0.0;
  uint64_t below = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    below += h[i];
    if (double(below) >= q * double(total))
      return i + 1 == h.size() ? INFINITY : double((i + 1) * PHOTON_VISIT_BIN_WIDTH);
  }
  return INFINITY;
}

uint32_t default_photons_per_pass(int width, int height) {
  const uint64_t pixels = uint64_t(std::max(1, width)) * uint64_t(std::max(1, height));
  return uint32_t(std::clamp<uint64_t>(pixels, 1u << 14, 1u << 20));
}

PhotonPass::PhotonPass(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                       const DeviceLights& lights, const RenderSettings& settings,
                       PhotonGather gather)
    : gather_mode_(gather),
      launcher_(launcher),
      scene_(scene),
      lights_(lights),
      light_count_(uint32_t(lights.count())),
      photons_per_pass_(settings.photons_per_pass > 0 ? settings.photons_per_pass
                                                      : default_photons_per_pass(settings.width, settings.height)),
      max_depth_(uint32_t(std::max(0, scene.scene().nbounces))),
      seed_(settings.seed),
      pixel_count_(size_t(settings.width) * size_t(settings.height)),
      first_cell_size_(settings.caustic_radius > 0.0f ? settings.caustic_radius
                                                      : camera_footprint_at_focus(scene.scene(), settings.height)),
      cell_size_(first_cell_size_),
      fixed_radius_(settings.caustic_radius > 0.0f),
      emit_(program, "emit_photons"),
      intersect_(program, "intersect_closest"),
      bounce_(program, "bounce_photons"),
      compact_(program, "compact_photons"),
      scan_(program),
      grid_(launcher.runtime(), program) {
  auto& ctx = launcher.runtime().context();
  const size_t n = photons_per_pass_;
  for (DeviceQueue& q : queues_) q = DeviceQueue(ctx, photon_record_layout(), n);
  hits_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Hit));
  loop_ = std::make_unique<WaveLoop>(launcher, std::vector<int>{1});  // extra counter 0: photon rays traced
  candidates_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Photon));
  stored_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  offsets_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, (n + 1) * sizeof(cl_uint));
  photons_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Photon));
  stored_count_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  if (settings.kernel_shape == KernelShape::Paths) {
    paths_shape_ = true;
    trace_ = StageKernel(program, "trace_photons");
    progress_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint));
    launcher.runtime().fill(progress_, cl_uint(0), 0, 2 * sizeof(cl_uint));
  }
  if (gather_mode_ == PhotonGather::PerPixel) {
    gather_ = StageKernel(program, "gather_photons");
    visible_points_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixel_count_ * sizeof(VisiblePoint));
    pixels_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixel_count_ * sizeof(SppmPixel));
    gather_counters_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, GATHER_COUNTERS * sizeof(cl_ulong));
  }
  const std::vector<cs_float4> bounds = settings.photon_guiding ? caster_bounds(scene.scene()) : std::vector<cs_float4>{};
  caster_count_ = uint32_t(bounds.size());
  casters_ = bounds.empty() ? cl::Buffer(ctx, CL_MEM_READ_ONLY, sizeof(cs_float4)) : upload_buffer(ctx, bounds);
  // Any origin works (cells are hashed); the camera's keeps the cells a
  // query meets near it small numbers.
  const glm::vec3 eye = scene.scene().camera.position;
  origin_ = {eye.x, eye.y, eye.z};
  pixel_end_ = pixel_count_;
  photon_end_ = photons_per_pass_;
  clear();
}

void PhotonPass::share(PixelShare* share) {
  if (gather_mode_ != PhotonGather::PerPixel)
    throw Error("photon pass: only path mode's per-pixel statistics are shared by pixels");
  share_ = share && share->size() > 1 ? share : nullptr;
  const int rank = share_ ? share_->rank() : 0, size = share_ ? share_->size() : 1;
  std::tie(first_pixel_, pixel_end_) = share_of(pixel_count_, rank, size);
  const auto [first, end] = share_of(photons_per_pass_, rank, size);
  first_photon_ = uint32_t(first);
  photon_end_ = uint32_t(end);
}

std::string PhotonPass::pixel_slice(bool whole_state) const {
  const size_t n = pixel_end_ - first_pixel_;
  const size_t counters = GATHER_COUNTERS * sizeof(cl_ulong);
  std::string out(n * sizeof(SppmPixel) + (whole_state ? n * sizeof(VisiblePoint) + counters : 0), '\0');
  auto& queue = launcher_.runtime().queue();
  if (n > 0)
    queue.enqueueReadBuffer(pixels_, CL_TRUE, first_pixel_ * sizeof(SppmPixel), n * sizeof(SppmPixel), out.data());
  if (!whole_state) return out;
  if (n > 0)
    queue.enqueueReadBuffer(visible_points_, CL_TRUE, first_pixel_ * sizeof(VisiblePoint), n * sizeof(VisiblePoint),
                            out.data() + n * sizeof(SppmPixel));
  queue.enqueueReadBuffer(gather_counters_, CL_TRUE, 0, counters, out.data() + n * (sizeof(SppmPixel) + sizeof(VisiblePoint)));
  return out;
}

void PhotonPass::put_pixel_slices(const std::vector<std::string>& by_rank) {
  if (!share_) return;
  if (by_rank.size() != size_t(share_->size()))
    throw Error("photon pass: " + std::to_string(by_rank.size()) + " pixel slices for " +
                std::to_string(share_->size()) + " processes");
  auto& queue = launcher_.runtime().queue();
  const size_t counters = GATHER_COUNTERS * sizeof(cl_ulong);
  others_counters_.assign(GATHER_COUNTERS, 0);
  for (int r = 0; r < share_->size(); ++r) {
    if (r == share_->rank()) continue;
    const auto [first, end] = share_of(pixel_count_, r, share_->size());
    const size_t n = end - first;
    const std::string& bytes = by_rank[size_t(r)];
    const bool whole_state = bytes.size() == n * (sizeof(SppmPixel) + sizeof(VisiblePoint)) + counters;
    if (!whole_state && bytes.size() != n * sizeof(SppmPixel))
      throw Error("photon pass: process " + std::to_string(r) + " sent " + std::to_string(bytes.size()) +
                  " bytes of SPPM pixels for its " + std::to_string(n) + " pixels");
    if (n > 0)
      queue.enqueueWriteBuffer(pixels_, CL_TRUE, first * sizeof(SppmPixel), n * sizeof(SppmPixel), bytes.data());
    if (!whole_state) continue;
    if (n > 0)
      queue.enqueueWriteBuffer(visible_points_, CL_TRUE, first * sizeof(VisiblePoint), n * sizeof(VisiblePoint),
                               bytes.data() + n * sizeof(SppmPixel));
    // Its gather counters since the latest map (the passes' inline
    // gathers, which `auto` weighs at the next map): the state's are the
    // sum over the processes.
    std::vector<uint64_t> c(GATHER_COUNTERS);
    std::memcpy(c.data(), bytes.data() + n * (sizeof(SppmPixel) + sizeof(VisiblePoint)), counters);
    for (size_t i = 0; i < c.size(); ++i) others_counters_[i] += c[i];
  }
}

void PhotonPass::gather_pixels_to_all() {
  if (!share_) return;
  const std::string all = share_->gather_bytes_to_all(pixel_slice(false));
  if (all.size() != pixel_count_ * sizeof(SppmPixel))
    throw Error("photon pass: " + std::to_string(all.size()) + " bytes of SPPM pixels gathered for " +
                std::to_string(pixel_count_) + " pixels");
  // Windows in rank order are the pixels in order: the whole buffer (this
  // process's own window comes back unchanged).
  if (!all.empty()) launcher_.runtime().queue().enqueueWriteBuffer(pixels_, CL_TRUE, 0, all.size(), all.data());
}

void PhotonPass::zero_counters() {
  if (gather_mode_ == PhotonGather::PerPixel)
    launcher_.runtime().fill(gather_counters_, cl_ulong(0), 0, GATHER_COUNTERS * sizeof(cl_ulong));
}

void PhotonPass::exchange_photons(RenderStats* stats) {
  Runtime& rt = launcher_.runtime();
  const uint32_t mine = launcher_.read_count(stored_count_, stats);
  std::string bytes(size_t(mine) * sizeof(Photon), '\0');
  if (mine > 0) rt.queue().enqueueReadBuffer(photons_, CL_TRUE, 0, bytes.size(), bytes.data());
  // The map's total first: its wait is the ranks' imbalance (the slowest
  // one's photons and pixels), the gather after it the transfer.
  auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<uint64_t> count = {mine};
  share_->sum_to_all(count);
  traffic_.wait_seconds += since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  const std::string all = share_->gather_bytes_to_all(bytes);
  traffic_.gather_seconds += since(t1);
  if (all.size() != count[0] * sizeof(Photon))
    throw Error("photon pass: " + std::to_string(all.size()) + " bytes of photons gathered, " +
                std::to_string(count[0]) + " photons counted");
  // A photon path stores one photon at most: the map fits the buffer.
  const size_t total = all.size() / sizeof(Photon);
  if (total > photons_per_pass_)
    throw Error("photon pass: " + std::to_string(total) + " photons gathered for a map of " +
                std::to_string(photons_per_pass_));
  if (!all.empty()) rt.queue().enqueueWriteBuffer(photons_, CL_TRUE, 0, all.size(), all.data());
  launcher_.write_count(stored_count_, uint32_t(total), stats);
  traffic_.bytes += all.size();
}

PhotonPass::~PhotonPass() = default;

void PhotonPass::clear() {
  others_counters_.clear();
  cell_size_ = first_cell_size_;
  on_ = true;
  maps_ = gathered_ = 0;
  spp_while_on_.clear();
  last_gathers_ = {};
  last_photon_rays_ = last_stored_ = 0;
  stats_ = {};
  if (gather_mode_ != PhotonGather::PerPixel) return;
  SppmPixel start{};  // radius2 0: set by the pixel's first visible point
  launcher_.runtime().fill(pixels_, start, 0, pixel_count_ * sizeof(SppmPixel));
  launcher_.runtime().fill(visible_points_, cl_uint(0), 0, pixel_count_ * sizeof(VisiblePoint));
}

float PhotonPass::shared_radius(uint32_t map_index) const {
  const double r0 = first_cell_size_;
  double r2 = r0 * r0;
  for (uint32_t i = 1; i <= map_index; ++i) r2 *= (i + double(kSppmAlpha)) / (i + 1.0);
  return float(std::sqrt(r2));
}

float PhotonPass::later_receiver_radius() const {
  if (!on_ || maps_ == 0) return 0.0f;
  return std::min(shared_radius(maps_ - 1), cell_size_);
}

KernelArgs& PhotonPass::bind_photon_map(KernelArgs& args) const {
  const uint32_t latest = maps_ > 0 ? maps_ - 1 : 0;
  if (gather_mode_ == PhotonGather::SharedRadius) return grid_.bind(args).arg("caustic_radius", shared_radius(latest));
  return grid_.bind(args)
      .arg("caustic_radius", later_receiver_radius())
      .arg("gather_counters", gather_counters_);
}

PhotonPassParams PhotonPass::params(uint32_t map_index) const {
  PhotonPassParams p{};
  p.photon_count = photons_per_pass_;
  p.light_count = light_count_;
  p.pass_index = map_index;
  p.seed = seed_;
  p.max_depth = max_depth_;
  p.pixel_count = cl_uint(pixel_count_);
  p.alpha = kSppmAlpha;
  // With --caustic-radius every pixel starts there; otherwise at its
  // footprint; never above one cell of this pass's grid.
  p.radius_cap = fixed_radius_ ? std::min(first_cell_size_, cell_size_) : cell_size_;
  p.footprint_radius = fixed_radius_ ? 0u : 1u;
  p.first_photon = first_photon_;
  p.photon_end = photon_end_;
  p.first_pixel = cl_uint(first_pixel_);
  p.pixel_end = cl_uint(pixel_end_);
  return p;
}

void PhotonPass::trace_wavefront(const PhotonPassParams& p, RenderStats* stats) {
  KernelArgs emit(emit_);
  scene_.bind_scene_buffers(emit, lights_)
      .arg("params", p)
      .arg("casters", casters_)
      .arg("caster_count", caster_count_)
      .queue("out", queues_[0], loop_->traced_count(0))
      .arg("next_count", loop_->pushed_count(0))
      .finish();
  // This process's photons only (all of them in one process); the flags
  // of the others stay 0, so the compaction packs its share from slot 0.
  const uint32_t traced = photon_end_ - first_photon_;
  launcher_.runtime().fill(stored_, cl_uint(0), 0, size_t(photons_per_pass_) * sizeof(cl_uint));
  if (traced > 0) launcher_.launch(emit_, traced, stats);
  auto enqueue = [&](uint32_t j, size_t bound) {
    const DeviceQueue& current = queues_[j % 2];
    const DeviceQueue& next = queues_[(j + 1) % 2];
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", current, loop_->traced_count(j)).arg("hits", hits_).finish();
    launcher_.launch(intersect_, bound, stats);
    KernelArgs bounce(bounce_);
    scene_.bind_scene_buffers(bounce, lights_)
        .arg("params", p)
        .queue("in", current, loop_->traced_count(j))
        .arg("hits", hits_)
        .queue("next", next, loop_->pushed_count(j))
        .arg("ray_capacity", cl_uint(photons_per_pass_))
        .arg("cleared_count", loop_->cleared_count(j))
        .arg("rays_traced", loop_->extra(0))
        .arg("candidates", candidates_)
        .arg("stored", stored_)
        .finish();
    launcher_.launch(bounce_, bound, stats);
  };
  // A photon continues once at most: the counts only fall.
  auto decide = [&](const WaveLoop::Counters& after, uint32_t seen) -> size_t {
    const cl_uint remaining = std::min(after.queue_count(seen + 1), photons_per_pass_);
    return remaining == 0 ? WaveLoop::kStop : remaining;
  };
  if (traced > 0) loop_->run(traced, ~0u, enqueue, decide, stats);
  const cl_uint rays = traced > 0 ? loop_->last().extra(0) - photon_rays_seen_ : 0u;  // the counter runs over the render (mod 2^32)
  photon_rays_seen_ += rays;
  if (stats) stats->photon_rays += rays;
  last_photon_rays_ = rays;
}

// The paths shape: each work-item takes this process's next photon and
// follows it to its end (trace_photons.cl); the same photon map.
void PhotonPass::trace_paths(const PhotonPassParams& p, RenderStats* stats) {
  const uint32_t traced = photon_end_ - first_photon_;
  launcher_.runtime().fill(stored_, cl_uint(0), 0, size_t(photons_per_pass_) * sizeof(cl_uint));
  launcher_.runtime().fill(progress_, cl_uint(0), 0, sizeof(cl_uint));
  KernelArgs trace(trace_);
  scene_.bind_scene_buffers(trace, lights_)
      .arg("params", p)
      .arg("casters", casters_)
      .arg("caster_count", caster_count_)
      .arg("candidates", candidates_)
      .arg("stored", stored_)
      .arg("progress", progress_)
      .finish();
  const size_t workers =
      std::max<size_t>(1, launcher_.runtime().device_info().compute_units) * launcher_.local_size();
  if (traced > 0) launcher_.launch(trace_, workers, stats);
  cl_uint progress[2] = {0, 0};
  launcher_.runtime().queue().enqueueReadBuffer(progress_, CL_TRUE, 0, sizeof progress, progress);
  if (stats) ++stats->blocking_transfers;
  const cl_uint rays = progress[1] - photon_rays_seen_;  // the counter runs over the render (mod 2^32)
  photon_rays_seen_ += rays;
  if (stats) stats->photon_rays += rays;
  last_photon_rays_ = rays;
}

void PhotonPass::trace(RenderStats* stats) {
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t pass_index = maps_++;
  if (gather_mode_ == PhotonGather::PerPixel && pass_index == 0)
    launcher_.runtime().fill(gather_counters_, cl_ulong(0), 0, GATHER_COUNTERS * sizeof(cl_ulong));
  last_photon_rays_ = 0;
  const PhotonPassParams p = params(pass_index);
  if (paths_shape_) {
    trace_paths(p, stats);
  } else {
    trace_wavefront(p, stats);
  }
  // Stored photons packed in photon order: offsets = exclusive scan of the
  // flags, whose last entry (a 0 appended) becomes the total.
  launcher_.runtime().copy(stored_, offsets_, 0, 0, size_t(photons_per_pass_) * sizeof(cl_uint));
  launcher_.runtime().fill(offsets_, cl_uint(0), size_t(photons_per_pass_) * sizeof(cl_uint), sizeof(cl_uint));
  scan_.run(launcher_, offsets_, size_t(photons_per_pass_) + 1, stats);
  KernelArgs(compact_)
      .arg("candidates", candidates_)
      .arg("stored", stored_)
      .arg("offsets", offsets_)
      .arg("photon_count", cl_uint(photons_per_pass_))
      .arg("photons", photons_)
      .finish();
  launcher_.launch(compact_, photons_per_pass_, stats);
  launcher_.runtime().copy(offsets_, stored_count_, size_t(photons_per_pass_) * sizeof(cl_uint), 0, sizeof(cl_uint));
  if (share_) exchange_photons(stats);
  PhotonGridShape shape;
  shape.origin = origin_;
  if (gather_mode_ == PhotonGather::SharedRadius) cell_size_ = shared_radius(pass_index);
  shape.cell_size = map_cell_size_ = cell_size_;
  const uint32_t stored = grid_.build(launcher_, photons_, stored_count_, photons_per_pass_, shape, stats);
  stats_.emitted += photons_per_pass_;
  stats_.stored += stored;
  stats_.photon_rays += last_photon_rays_;
  last_stored_ = stored;
  stats_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

namespace {
std::string read_bytes(Runtime& runtime, const cl::Buffer& buffer, size_t bytes) {
  std::string out(bytes, '\0');
  if (bytes > 0) runtime.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, bytes, out.data());
  return out;
}
void write_bytes(Runtime& runtime, const cl::Buffer& buffer, const std::string& bytes, size_t expected,
                 const std::string& what) {
  if (bytes.size() != expected)
    throw Error("photon pass state: " + std::to_string(bytes.size()) + " bytes of " + what + ", " +
                std::to_string(expected) + " expected");
  if (expected > 0) runtime.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, expected, bytes.data());
}
}  // namespace

void PhotonPass::save(StateWriter& out) const {
  Runtime& rt = launcher_.runtime();
  out.put(maps_);
  out.put(gathered_);
  out.put(uint8_t(on_ ? 1 : 0));
  out.put(cell_size_);
  out.put(map_cell_size_);
  out.array(spp_while_on_);
  out.array(std::vector<uint64_t>(radii_.begin(), radii_.end()));
  const bool per_pixel = gather_mode_ == PhotonGather::PerPixel;
  out.blob(per_pixel ? read_bytes(rt, pixels_, pixel_count_ * sizeof(SppmPixel)) : std::string());
  out.blob(per_pixel ? read_bytes(rt, visible_points_, pixel_count_ * sizeof(VisiblePoint)) : std::string());
  std::string counters = per_pixel ? read_bytes(rt, gather_counters_, GATHER_COUNTERS * sizeof(cl_ulong)) : std::string();
  if (per_pixel && others_counters_.size() == GATHER_COUNTERS) {
    // Shared by pixels (rank 0 for the whole render's state): every other
    // process's counters added.
    std::vector<uint64_t> c(GATHER_COUNTERS);
    std::memcpy(c.data(), counters.data(), counters.size());
    for (size_t i = 0; i < c.size(); ++i) c[i] += others_counters_[i];
    std::memcpy(counters.data(), c.data(), counters.size());
  }
  out.blob(counters);
  // The latest map: its stored photons (the counter may have run past the
  // buffer: the grid holds at most photons_per_pass_ of them).
  out.put(uint64_t(last_stored_));
  const size_t kept = maps_ > 0 ? std::min<uint64_t>(last_stored_, photons_per_pass_) : 0;
  out.blob(read_bytes(rt, photons_, kept * sizeof(Photon)));
}

void PhotonPass::load(StateReader& in) {
  Runtime& rt = launcher_.runtime();
  maps_ = in.get<uint32_t>("photon pass");
  gathered_ = in.get<uint32_t>("photon pass");
  on_ = in.get<uint8_t>("photon pass") != 0;
  cell_size_ = in.get<float>("photon pass");
  map_cell_size_ = in.get<float>("photon pass");
  spp_while_on_ = in.array<uint32_t>("photon pass's samples while on");
  const std::vector<uint64_t> radii = in.array<uint64_t>("photon radius histogram");
  if (radii.size() != radii_.size())
    throw Error("photon pass state: a radius histogram of " + std::to_string(radii.size()) + " bins, " +
                std::to_string(radii_.size()) + " expected");
  std::copy(radii.begin(), radii.end(), radii_.begin());
  const bool per_pixel = gather_mode_ == PhotonGather::PerPixel;
  write_bytes(rt, pixels_, in.blob("SPPM pixels"), per_pixel ? pixel_count_ * sizeof(SppmPixel) : 0, "SPPM pixels");
  write_bytes(rt, visible_points_, in.blob("visible points"), per_pixel ? pixel_count_ * sizeof(VisiblePoint) : 0,
              "visible points");
  write_bytes(rt, gather_counters_, in.blob("gather counters"), per_pixel ? GATHER_COUNTERS * sizeof(cl_ulong) : 0,
              "gather counters");
  const uint64_t stored = in.get<uint64_t>("photon map");
  const std::string photons = in.blob("photon map");
  const size_t kept = maps_ > 0 ? std::min<uint64_t>(stored, photons_per_pass_) : 0;
  write_bytes(rt, photons_, photons, kept * sizeof(Photon), "photons");
  last_stored_ = stored;
  if (maps_ == 0) return;
  // The latest map's grid, built again from its photons and cells.
  const cl_uint counter = cl_uint(std::min<uint64_t>(stored, 0xFFFFFFFFull));
  rt.queue().enqueueWriteBuffer(stored_count_, CL_TRUE, 0, sizeof counter, &counter);
  PhotonGridShape shape;
  shape.origin = origin_;
  shape.cell_size = map_cell_size_;
  grid_.build(launcher_, photons_, stored_count_, photons_per_pass_, shape);
}

void PhotonPass::gather(RenderStats* stats) {
  if (maps_ == 0) return;
  const auto t0 = std::chrono::steady_clock::now();
  KernelArgs gather(gather_);
  gather.arg("params", params(maps_ - 1));
  grid_.bind(gather)
      .arg("visible_points", visible_points_)
      .arg("pixels", pixels_)
      .arg("gather_counters", gather_counters_)
      .finish();
  launcher_.launch(gather_, pixel_end_ - first_pixel_, stats);
  ++gathered_;
  read_counters(stats, /*summed=*/true);
  stats_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The next grid's cells follow the visible points' radii.
  uint64_t radii = 0;
  for (uint64_t c : radii_) radii += c;
  if (radii == 0) return;  // no visible point: the cells stay
  uint64_t below = 0;
  for (uint32_t i = 0; i < PHOTON_RADIUS_BINS; ++i) {
    below += radii_[i];
    if (double(below) >= kCellQuantile * double(radii)) {
      // bin i holds radii in [2^((i - 128) / 4), 2^((i - 127) / 4)) (radii
      // never grow, and are at most one cell, so the cells follow them
      // down, and up no further than the first footprints).
      const float edge = float(std::exp2((int(i) - 127) / 4.0));
      if (edge > 0.0f && std::isfinite(edge)) cell_size_ = edge;
      break;
    }
  }
}

void PhotonPass::read_counters(RenderStats* stats) { read_counters(stats, false); }

void PhotonPass::read_counters(RenderStats* stats, bool summed) {
  if (gather_mode_ != PhotonGather::PerPixel) return;
  std::vector<uint64_t> c(GATHER_COUNTERS, 0);
  launcher_.runtime().queue().enqueueReadBuffer(gather_counters_, CL_TRUE, 0, c.size() * sizeof(cl_ulong), c.data());
  launcher_.runtime().fill(gather_counters_, cl_ulong(0), 0, GATHER_COUNTERS * sizeof(cl_ulong));
  if (stats) ++stats->blocking_transfers;
  // Shared by pixels: the whole image's counts (the radius histogram sizes
  // every process's next cells alike).
  if (summed && share_) share_->sum_to_all(c);
  PhotonGatherStats g;
  g.visits_d1 = c[GATHER_COUNT_VISITS_D1];
  g.visits_later = c[GATHER_COUNT_VISITS_LATER];
  for (uint32_t i = 0; i < PHOTON_VISIT_BINS; ++i) {
    g.histogram_d1[i] = c[GATHER_COUNT_HISTOGRAM_D1 + i];
    g.histogram_later[i] = c[GATHER_COUNT_HISTOGRAM_LATER + i];
    g.gathers_d1 += g.histogram_d1[i];
    g.gathers_later += g.histogram_later[i];
  }
  for (uint32_t i = 0; i < PHOTON_RADIUS_BINS; ++i) radii_[i] = c[GATHER_COUNT_RADIUS + i];
  last_gathers_ = g;
  stats_.gathers.add(g);
}

double PhotonPass::film_share(size_t p, const std::vector<uint32_t>& spp) const {
  if (p >= spp.size() || spp[p] == 0) return 0.0;
  if (on_ || spp_while_on_.empty()) return 1.0;
  return std::min(1.0, double(spp_while_on_[p]) / double(spp[p]));
}

std::vector<SppmPixel> PhotonPass::read_pixels() const {
  std::vector<SppmPixel> px(pixel_count_);
  launcher_.runtime().queue().enqueueReadBuffer(pixels_, CL_TRUE, 0, px.size() * sizeof(SppmPixel), px.data());
  return px;
}

double PhotonPass::caustic_total(const std::vector<uint32_t>& spp) const {
  if (gather_mode_ != PhotonGather::PerPixel || gathered_ == 0) return 0.0;
  double total = 0.0;
  const std::vector<SppmPixel> px = read_pixels();
  for (size_t i = 0; i < px.size(); ++i)
    if (px[i].radius2 > 0.0f)
      total += film_share(i, spp) * (double(px[i].tau.x) + px[i].tau.y + px[i].tau.z) /
               (double(gathered_) * M_PI * px[i].radius2);
  return total;
}

void PhotonPass::add_error_to(ImageF& variance, ImageF& bias2, const std::vector<uint32_t>& spp) const {
  if (gather_mode_ != PhotonGather::PerPixel || gathered_ == 0) return;
  const std::vector<SppmPixel> px = read_pixels();
  const double n = gathered_;
  const int width = variance.width, height = variance.height;
  if (bias2.width != width || bias2.height != height) return;
  if (size_t(width) * size_t(height) != pixel_count_) return;
  // The variance of each pixel's caustic radiance (its noise).
  std::vector<double> noise(3 * pixel_count_, 0.0), radiance(3 * pixel_count_, 0.0);
  for (size_t i = 0; i < pixel_count_; ++i) {
    if (!(px[i].radius2 > 0.0f)) continue;
    const double share = film_share(i, spp);
    // A map's estimate L_k has variance c / r_k^2; c from the spread of the
    // maps' estimates (passes without a visible point add L = 0 and r = 0),
    // and the pixel's estimate, a mean over n maps at its current radius r,
    // c / (n r^2). At least a density estimate's own Poisson noise, L^2 / N
    // for the N photons it holds: the only figure a single map gives
    // (issue 45: an estimate of one map had reported no error at all),
    // and a floor where a few maps happen to agree.
    const double r2_sum = px[i].sum_r2;
    const float sum[3] = {px[i].sum_l.x, px[i].sum_l.y, px[i].sum_l.z};
    const float sum2[3] = {px[i].sum_l2.x, px[i].sum_l2.y, px[i].sum_l2.z};
    const float tau[3] = {px[i].tau.x, px[i].tau.y, px[i].tau.z};
    for (int c = 0; c < 3; ++c) {
      radiance[3 * i + c] = share * tau[c] / (n * M_PI * px[i].radius2);
      const double poisson =
          px[i].photons > 0.0f ? radiance[3 * i + c] * radiance[3 * i + c] / double(px[i].photons) : 0.0;
      double spread = 0.0;
      if (n >= 2.0) {
        const double mean = sum[c] / n;
        spread = share * share * std::max(0.0, (sum2[c] - mean * mean * r2_sum) / (n - 1.0)) /
                 (n * double(px[i].radius2));
      }
      noise[3 * i + c] = std::max(spread, poisson);
    }
  }
  // Its bias: a disk of radius r averages L to L + r^2 / 8 lap L, and the
  // radius in pixels is about r / r_0 (r_0 was one footprint), so bias ~
  // (r / r_0)^2 / 8 times the image's 5-point Laplacian; its square less
  // the Laplacian's own noise (the neighbours' variances plus 16 times the
  // pixel's) estimates the squared bias (Hachisuka et al. 2010 estimate
  // SPPM's bias from the Laplacian the same way). Kept apart from the
  // noise, which the neighbours' Laplacians read.
  std::vector<double> squared_bias(3 * pixel_count_, 0.0);
  auto at = [&](int x, int y) { return size_t(y) * size_t(width) + size_t(x); };
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      const size_t i = at(x, y);
      if (!(px[i].radius2 > 0.0f && px[i].footprint2 > 0.0f)) continue;
      const double rho2 = double(px[i].radius2) / double(px[i].footprint2);
      const size_t nb[4] = {at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)};
      for (int c = 0; c < 3; ++c) {
        double lap = -4.0 * radiance[3 * i + c], lap_noise = 16.0 * noise[3 * i + c];
        for (size_t j : nb) {
          lap += radiance[3 * j + c];
          lap_noise += noise[3 * j + c];
        }
        const double bias = rho2 / 8.0;
        squared_bias[3 * i + c] = bias * bias * std::max(0.0, lap * lap - lap_noise);
      }
    }
  for (size_t i = 0; i < 3 * pixel_count_; ++i) {
    variance.rgb[i] += float(noise[i]);
    bias2.rgb[i] += float(squared_bias[i]);
  }
}

void PhotonPass::add_to(ImageF& image, const std::vector<uint32_t>& spp) const {
  if (gather_mode_ != PhotonGather::PerPixel) return;  // phong's caustics are in the film's passes
  if (gathered_ == 0) return;
  const std::vector<SppmPixel> px = read_pixels();
  for (size_t i = 0; i < pixel_count_ && i < image.pixel_count(); ++i) {
    const double scale =
        px[i].radius2 > 0.0f ? film_share(i, spp) / (double(gathered_) * M_PI * px[i].radius2) : 0.0;
    const float tau[3] = {px[i].tau.x, px[i].tau.y, px[i].tau.z};
    for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] += float(tau[c] * scale);
  }
}

}  // namespace caustica
