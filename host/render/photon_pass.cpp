#include "host/render/photon_pass.h"

#include <algorithm>
#include <cmath>

#include "host/cl/runtime.h"
#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/scene/scene.h"

namespace caustica {
namespace {

constexpr float kSppmAlpha = 2.0f / 3.0f;  // Hachisuka & Jensen's choice (the issue's)

// The scene's bounding box: the grid's origin and the default radius.
void scene_box(const Scene& scene, glm::vec3* lo, glm::vec3* hi) {
  *lo = glm::vec3(INFINITY);
  *hi = glm::vec3(-INFINITY);
  auto grow = [&](glm::vec3 p, float r) {
    *lo = glm::min(*lo, p - r);
    *hi = glm::max(*hi, p + r);
  };
  for (const Sphere& s : scene.spheres) grow(to_vec3(s.center_radius), s.center_radius.w);
  for (const Cylinder& c : scene.cylinders)
    grow(to_vec3(c.center_radius), c.center_radius.w + c.axis_half.w);  // the axis is a unit vector
  for (const Triangle& t : scene.triangles)
    for (const cs_float4& v : {t.v0, t.v1, t.v2}) grow(to_vec3(v), 0.0f);
  if (!(lo->x <= hi->x)) *lo = *hi = glm::vec3(0.0f);
}

}  // namespace

float default_caustic_radius(const Scene& scene, uint32_t photons_per_pass) {
  glm::vec3 lo, hi;
  scene_box(scene, &lo, &hi);
  const glm::vec3 e = hi - lo;
  const double area = 2.0 * (double(e.x) * e.y + double(e.y) * e.z + double(e.z) * e.x);
  const double diagonal = glm::length(e);
  const double r = std::sqrt(32.0 * area / (M_PI * std::max<uint32_t>(1, photons_per_pass)));
  const double capped = std::min(r, 0.005 * diagonal);
  return float(capped > 0.0 ? capped : 1e-3);
}

uint32_t default_photons_per_pass(int width, int height) {
  const uint64_t pixels = uint64_t(std::max(1, width)) * uint64_t(std::max(1, height));
  return uint32_t(std::clamp<uint64_t>(pixels, 1u << 14, 1u << 20));
}

PhotonPass::PhotonPass(StageLauncher& launcher, const DeviceScene& scene, const cl::Program& program,
                       const cl::Buffer& lights, uint32_t light_count, const RenderSettings& settings,
                       PhotonGather gather)
    : gather_mode_(gather),
      launcher_(launcher),
      scene_(scene),
      lights_(lights),
      light_count_(light_count),
      photons_per_pass_(settings.photons_per_pass > 0 ? settings.photons_per_pass
                                                      : default_photons_per_pass(settings.width, settings.height)),
      max_depth_(uint32_t(std::max(0, scene.scene().nbounces))),
      seed_(settings.seed),
      pixel_count_(size_t(settings.width) * size_t(settings.height)),
      initial_radius_(settings.caustic_radius > 0.0f ? settings.caustic_radius
                                                     : default_caustic_radius(scene.scene(), photons_per_pass_)),
      cell_size_(initial_radius_),
      fixed_radius_(settings.caustic_radius > 0.0f),
      image_height_(settings.height),
      emit_(program, "emit_photons"),
      intersect_(program, "intersect_closest"),
      bounce_(program, "bounce_photons"),
      compact_(program, "compact_photons"),
      scan_(program),
      grid_(launcher.runtime(), program) {
  auto& ctx = launcher.runtime().context();
  const size_t n = photons_per_pass_;
  for (DeviceQueue& q : queues_) q = DeviceQueue(ctx, path_record_layout(), n);
  hits_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Hit));
  candidates_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Photon));
  stored_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  offsets_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, (n + 1) * sizeof(cl_uint));
  photons_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(Photon));
  stored_count_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  if (gather_mode_ == PhotonGather::PerPixel) {
    gather_ = StageKernel(program, "gather_photons");
    visible_points_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixel_count_ * sizeof(VisiblePoint));
    pixels_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixel_count_ * sizeof(SppmPixel));
    largest_radius2_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  }
  glm::vec3 lo, hi;
  scene_box(scene.scene(), &lo, &hi);
  origin_ = {lo.x, lo.y, lo.z};
  clear();
}

PhotonPass::~PhotonPass() = default;

void PhotonPass::clear() {
  cell_size_ = initial_radius_;
  stats_ = {};
  if (gather_mode_ != PhotonGather::PerPixel) return;
  SppmPixel start{};  // radius2 0: set by the pixel's first visible point
  launcher_.runtime().fill(pixels_, start, 0, pixel_count_ * sizeof(SppmPixel));
  launcher_.runtime().fill(visible_points_, cl_uint(0), 0, pixel_count_ * sizeof(VisiblePoint));
}

float PhotonPass::shared_radius(uint32_t pass_index) const {
  double r2 = double(initial_radius_) * initial_radius_;
  for (uint32_t i = 1; i <= pass_index; ++i) r2 *= (i + double(kSppmAlpha)) / (i + 1.0);
  return float(std::sqrt(r2));
}

KernelArgs& PhotonPass::bind_photon_map(KernelArgs& args, uint32_t pass_index) const {
  return grid_.bind(args).arg("caustic_radius", shared_radius(pass_index));
}

PhotonPassParams PhotonPass::params(uint32_t pass_index) const {
  PhotonPassParams p{};
  p.photon_count = photons_per_pass_;
  p.light_count = light_count_;
  p.pass_index = pass_index;
  p.seed = seed_;
  p.max_depth = max_depth_;
  p.pixel_count = cl_uint(pixel_count_);
  p.alpha = kSppmAlpha;
  p.radius_cap = initial_radius_;
  // With --caustic-radius every pixel starts there; otherwise at its
  // footprint (the camera's angle per pixel times the distance), capped.
  const CameraDesc& cam = scene_.scene().camera;
  p.camera = to_float4(cam.position, fixed_radius_ ? 0.0f
                                                   : 2.0f * std::tan(glm::radians(cam.fov_y_degrees) * 0.5f) /
                                                         float(std::max(1, image_height_)));
  return p;
}

void PhotonPass::trace(uint32_t pass_index, RenderStats* stats) {
  const PhotonPassParams p = params(pass_index);
  DeviceQueue* current = &queues_[0];
  DeviceQueue* next = &queues_[1];
  KernelArgs(emit_).arg("lights", lights_).arg("params", p).queue("out", *current).finish();
  launcher_.launch(emit_, photons_per_pass_, stats);
  launcher_.write_count(current->count(), photons_per_pass_, stats);
  launcher_.runtime().fill(stored_, cl_uint(0), 0, size_t(photons_per_pass_) * sizeof(cl_uint));
  for (uint32_t count = photons_per_pass_; count > 0;) {
    KernelArgs intersect(intersect_);
    scene_.bind_geometry(intersect).ray_view("rays", *current).arg("hits", hits_).finish();
    launcher_.launch(intersect_, count, stats);
    launcher_.write_count(next->count(), 0, stats);
    KernelArgs bounce(bounce_);
    scene_.bind_surfaces(bounce)
        .arg("params", p)
        .queue("in", *current)
        .arg("hits", hits_)
        .queue("next", *next)
        .arg("ray_capacity", cl_uint(photons_per_pass_))
        .arg("candidates", candidates_)
        .arg("stored", stored_)
        .finish();
    launcher_.launch(bounce_, count, stats);
    if (stats) stats->photon_rays += count;
    count = std::min(launcher_.read_count(next->count(), stats), photons_per_pass_);
    std::swap(current, next);
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
  PhotonGridShape shape;
  shape.origin = origin_;
  if (gather_mode_ == PhotonGather::SharedRadius) cell_size_ = shared_radius(pass_index);
  shape.cell_size = cell_size_;
  const uint32_t stored = grid_.build(launcher_, photons_, stored_count_, photons_per_pass_, shape, stats);
  stats_.emitted += photons_per_pass_;
  stats_.stored += stored;
}

void PhotonPass::gather(uint32_t pass_index, RenderStats* stats) {
  launcher_.write_count(largest_radius2_, 0, stats);
  KernelArgs gather(gather_);
  gather.arg("params", params(pass_index));
  grid_.bind(gather)
      .arg("visible_points", visible_points_)
      .arg("pixels", pixels_)
      .arg("largest_radius2_bits", largest_radius2_)
      .finish();
  launcher_.launch(gather_, pixel_count_, stats);
  // The next grid's cells: the largest radius any pixel will query with,
  // so that a query visits at most 2 x 2 x 2 cells.
  const uint32_t bits = launcher_.read_count(largest_radius2_, stats);
  float radius2;
  std::memcpy(&radius2, &bits, sizeof radius2);
  if (radius2 > 0.0f && std::isfinite(radius2)) cell_size_ = std::sqrt(radius2);
}

void PhotonPass::add_to(ImageF& image, int passes) const {
  if (gather_mode_ != PhotonGather::PerPixel) return;  // phong's caustics are in the film's passes
  std::vector<SppmPixel> px(pixel_count_);
  launcher_.runtime().queue().enqueueReadBuffer(pixels_, CL_TRUE, 0, px.size() * sizeof(SppmPixel), px.data());
  for (size_t i = 0; i < pixel_count_ && i < image.pixel_count(); ++i) {
    const double scale = px[i].radius2 > 0.0f ? 1.0 / (double(passes) * M_PI * px[i].radius2) : 0.0;
    const float tau[3] = {px[i].tau.x, px[i].tau.y, px[i].tau.z};
    for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] += float(tau[c] * scale);
  }
}

}  // namespace caustica
