#include "tests/stiff/stiff_support.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "host/app/session.h"
#include "host/lights/light_types.h"
#include "tests/support/test_support.h"

namespace caustica::stiff {

namespace {
glm::vec3 map(const glm::vec3& p, float scale, glm::vec3 offset) { return scale * p + offset; }
void map4(cs_float4& p, float scale, glm::vec3 offset) {
  const glm::vec3 q = map(to_vec3(p), scale, offset);
  p.x = q.x, p.y = q.y, p.z = q.z;
}
}  // namespace

void transform_scene(Scene& s, float scale, glm::vec3 offset, bool point_light_falloff) {
  CameraDesc& c = s.camera;
  c.position = map(c.position, scale, offset);
  c.look_at = map(c.look_at, scale, offset);
  c.focus_distance *= scale;
  c.aperture_radius *= scale;
  for (Light& l : s.lights) {
    // Positions and sizes per type (kernels/lib/lights/<type>_light.h).
    const glm::vec3 p = map(to_vec3(l.p0), scale, offset);
    if (l.kind == LIGHT_POINT || l.kind == LIGHT_SPOT) {
      l.p0 = to_float4(p, l.p0.w);
      if (point_light_falloff) l.emitted = to_float4(to_vec3(l.emitted) * (scale * scale), 0.0f);
    } else if (l.kind == LIGHT_RECT) {
      l.p0 = to_float4(p);
      l.p1 = to_float4(to_vec3(l.p1) * scale);
      l.p2 = to_float4(to_vec3(l.p2) * scale);
      l.emitted.w = glm::length(glm::cross(to_vec3(l.p1), to_vec3(l.p2)));  // as the loader computes it
    } else if (l.kind == LIGHT_SPHERE) {
      const float r = l.p0.w * scale;
      l.p0 = to_float4(p, r);
      l.emitted.w = 4.0f * 3.14159265358979f * r * r;  // as the loader computes it
    } else {
      throw std::runtime_error("transform_scene: a file light of kind " + std::to_string(l.kind));
    }
  }
  for (auto& sp : s.spheres) {
    map4(sp.center_radius, scale, offset);
    sp.center_radius.w *= scale;
  }
  for (auto& cy : s.cylinders) {
    map4(cy.center_radius, scale, offset);
    cy.center_radius.w *= scale;
    cy.axis_half.w *= scale;
  }
  for (auto& t : s.triangles) {
    map4(t.v0, scale, offset);
    map4(t.v1, scale, offset);
    map4(t.v2, scale, offset);
  }
}

RenderResult render(const std::string& scene_path, RenderMode mode, int width, int height,
                    const std::function<void(Scene&)>& edit, int spp, size_t local_size) {
  SessionOptions o;
  o.scene_path = scene_path;
  o.mode = mode;
  o.width = width;
  o.height = height;
  o.device = test::device_spec();
  o.spp = spp;
  o.error_estimate = false;
  o.edit_scene = edit;
  o.local_size = local_size;
  // The photon pass sends at least 2^14 photons a pass whatever the image
  // size: 1024 on Oclgrind, where these renders are 16 x 12 to 60 x 40.
  if (test::on_simulator()) o.photons = 1024;
  auto session = prepare_session(o);
  RenderResult r;
  r.image = session->renderer->render(&r.stats);
  test::expect_finite_render(r.image, r.stats.film, scene_path);
  return r;
}

std::string official_scene(const std::string& name) {
  const std::string shared = test::shared_dir();
  if (!shared.empty()) {
    const std::string p = shared + "/scenes-coursework/official/" + name;
    if (std::filesystem::exists(p)) return p;
  }
  return test::source_dir() + "/scenes/" + name;
}

DeviceTracer::DeviceTracer(const Scene& scene, BvhBuildOptions::Quality quality,
                           const std::string& extra_build_options)
    : scene_(scene) {
  BvhBuildOptions options;
  options.quality = quality;
  bvh_ = build_bvh(scene_, options);
  wide_ = collapse_bvh(bvh_, scene_);
  features_ = analyse_scene(scene_, RenderMode::Binary);
  Runtime& rt = test::runtime();
  const BuiltProgram program = rt.build_file("integrator_binary.cl", features_.build_options() + " " + extra_build_options);
  device_ = std::make_unique<DeviceScene>(rt.context(), scene_, wide_, features_);
  kernel_ = StageKernel(program.program, "intersect_closest");
}

DeviceTracer::~DeviceTracer() = default;

std::vector<Hit> DeviceTracer::closest(const std::vector<glm::vec3>& origin, const std::vector<glm::vec3>& dir) const {
  std::vector<cs_float4> o, d;
  o.reserve(origin.size());
  d.reserve(dir.size());
  for (const auto& v : origin) o.push_back(to_float4(v));
  for (const auto& v : dir) d.push_back(to_float4(v));
  std::vector<Hit> hits(o.size());
  // Big batches go in slices: one launch of 10^6 rays is fine, but the
  // buffers of several at once are not needed.
  const size_t slice = 1u << 20;
  for (size_t first = 0; first < o.size(); first += slice) {
    const size_t n = std::min(slice, o.size() - first);
    const std::vector<cs_float4> so(o.begin() + first, o.begin() + first + n), sd(d.begin() + first, d.begin() + first + n);
    // As time_ray_kernel (host/bench/ray_batch.cpp) but one launch, no warm-up.
    auto& ctx = test::runtime().context();
    const std::vector<cl_uint> count{cl_uint(n)};
    const cl::Buffer count_buffer = upload_buffer(ctx, count), origin_buffer = upload_buffer(ctx, so),
                     dir_buffer = upload_buffer(ctx, sd);
    cl::Buffer result(ctx, CL_MEM_WRITE_ONLY, n * sizeof(Hit));
    KernelArgs args(kernel_);
    device_->bind_geometry(args)
        .arg("rays_count", count_buffer)
        .arg("rays_origin", origin_buffer)
        .arg("rays_dir", dir_buffer)
        .arg("hits", result)
        .finish();
    auto& queue = test::runtime().queue();
    queue.enqueueNDRangeKernel(kernel_.kernel, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
    queue.enqueueReadBuffer(result, CL_TRUE, 0, n * sizeof(Hit), hits.data() + first);
  }
  return hits;
}

double fraction_differing(const ImageF& a, const ImageF& b, float tol) {
  size_t off = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) {
    float m = 0.0f;
    for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(a.rgb[3 * i + c] - b.rgb[3 * i + c]));
    off += !(m <= tol);
  }
  return double(off) / double(std::max<size_t>(1, a.pixel_count()));
}

const ScaleCase kScaleCases[4] = {{"1e-4", 1e-4f, glm::vec3(0.0f)},
                                   {"1", 1.0f, glm::vec3(0.0f)},
                                   {"1e4", 1e4f, glm::vec3(0.0f)},
                                   {"offset_1e5", 1.0f, glm::vec3(1e5f, -1e5f, 1e5f)}};

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  return glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
}

double mean_abs_difference(const ImageF& a, const ImageF& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::fabs(double(a.rgb[i]) - double(b.rgb[i]));
  return sum / double(std::max<size_t>(1, a.rgb.size()));
}

}  // namespace caustica::stiff
