#include "host/render/wavefront.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "host/error.h"

namespace caustica {
namespace {

template <typename T, typename Allocator>
cl::Buffer upload(cl::Context& ctx, const std::vector<T, Allocator>& data) {
  // OpenCL forbids zero-sized buffers; an absent primitive type gets one
  // dummy element that no BVH leaf references.
  const size_t bytes = std::max<size_t>(1, data.size()) * sizeof(T);
  if (data.empty()) return cl::Buffer(ctx, CL_MEM_READ_ONLY, bytes);
  return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<T*>(data.data()));
}

}  // namespace

struct RayQueue {
  cl::Buffer origin, dir, weight, pixel, count;
  void allocate(cl::Context& ctx, size_t capacity) {
    origin = cl::Buffer(ctx, CL_MEM_READ_WRITE, capacity * sizeof(cs_float4));
    dir = cl::Buffer(ctx, CL_MEM_READ_WRITE, capacity * sizeof(cs_float4));
    weight = cl::Buffer(ctx, CL_MEM_READ_WRITE, capacity * sizeof(cs_float4));
    pixel = cl::Buffer(ctx, CL_MEM_READ_WRITE, capacity * sizeof(cl_uint));
    count = cl::Buffer(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
  }
};

namespace {

template <typename... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, args), ...);
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

struct WavefrontRenderer::Buffers {
  cl::Buffer nodes, triangle_blocks, prim_refs, spheres, cylinders, triangles, triangle_shading, materials, lights;
  cl::Buffer textures, texels;
  cl::Buffer film, hits;
  RayQueue rays[2];
  RayQueue shadow;  // "weight" holds the contribution
  size_t chunk = 0, ray_capacity = 0, shadow_capacity = 0;
};

WavefrontRenderer::WavefrontRenderer(Runtime& runtime, const Scene& scene, const WideBvh& bvh,
                                     const SceneFeatures& features, const cl::Program& program,
                                     const RenderSettings& settings)
    : runtime_(runtime), scene_(scene), features_(features), settings_(settings), buffers_(new Buffers) {
  if (settings_.width <= 0 || settings_.height <= 0) throw Error("render: image size must be positive");
  auto& ctx = runtime_.context();
  Buffers& b = *buffers_;
  try {
    b.nodes = upload(ctx, bvh.nodes);
    b.triangle_blocks = upload(ctx, bvh.triangle_blocks);
    b.prim_refs = upload(ctx, bvh.prim_refs);
    b.spheres = upload(ctx, scene.spheres);
    b.cylinders = upload(ctx, scene.cylinders);
    b.triangles = upload(ctx, scene.triangles);
    // Data the feature set leaves out is not uploaded (a dummy element).
    static const std::vector<TriangleShading> no_shading;
    static const std::vector<Texture> no_textures;
    static const std::vector<uint16_t> no_texels;
    b.triangle_shading = upload(ctx, features_.triangle_shading ? scene.triangle_shading : no_shading);
    b.materials = upload(ctx, scene.materials);
    b.textures = upload(ctx, features_.textures ? scene.textures : no_textures);
    b.texels = upload(ctx, features_.textures ? scene.texels : no_texels);
    b.lights = upload(ctx, scene.point_lights);

    const size_t pixels = size_t(settings_.width) * settings_.height;
    const size_t light_count = features_.lights ? scene.point_lights.size() : 0;
    // Queue memory grows with the chunk and the number of lights; keep the
    // shadow queue within ~2^21 entries.
    b.chunk = std::min(pixels, settings_.chunk_pixels);
    if (light_count > 0) b.chunk = std::min(b.chunk, std::max<size_t>(4096, (size_t(1) << 21) / light_count));
    // A wave can at most double (one reflection + one refraction child per ray).
    b.ray_capacity = features_.secondary_rays()
                         ? std::max(b.chunk, size_t(double(b.chunk) * settings_.queue_capacity_factor))
                         : b.chunk;
    b.shadow_capacity = std::max<size_t>(1, b.ray_capacity * light_count);
    b.film = cl::Buffer(ctx, CL_MEM_READ_WRITE, pixels * 3 * sizeof(cl_ulong));
    b.hits = cl::Buffer(ctx, CL_MEM_READ_WRITE, b.ray_capacity * sizeof(cs_float4));
    b.rays[0].allocate(ctx, b.ray_capacity);
    if (features_.secondary_rays()) b.rays[1].allocate(ctx, b.ray_capacity);
    b.shadow.allocate(ctx, b.shadow_capacity);

    generate_ = cl::Kernel(program, "generate_camera_rays");
    intersect_ = cl::Kernel(program, "intersect_closest");
    shade_ = cl::Kernel(program, "shade_surface");
    shadow_ = cl::Kernel(program, "intersect_shadow");
  } catch (const cl::Error& e) {
    throw Error(std::string("cannot set up the renderer on ") + runtime_.device_info().name + ": " + e.what() +
                " (" + cl_error_name(e.err()) + ")");
  }
}

WavefrontRenderer::~WavefrontRenderer() = default;

CameraGPU WavefrontRenderer::camera_for_chunk(size_t first_pixel, size_t pixel_count) const {
  const CameraBasis basis = camera_basis(scene_.camera);
  const float tan_half = std::tan(scene_.camera.fov_y_degrees * 0.5f * 3.14159265358979f / 180.0f);
  const float aspect = float(settings_.width) / float(settings_.height);
  CameraGPU cam{};
  cam.position = to_float4(scene_.camera.position);
  cam.forward = to_float4(basis.forward);
  cam.right = to_float4(basis.right * (tan_half * aspect));
  cam.up = to_float4(basis.up * tan_half);
  cam.width = cl_uint(settings_.width);
  cam.height = cl_uint(settings_.height);
  cam.pixel_offset = cl_uint(first_pixel);
  cam.pixel_count = cl_uint(pixel_count);
  return cam;
}

void WavefrontRenderer::launch(cl::Kernel& kernel, size_t count) {
  if (count == 0) return;
  const size_t local = settings_.local_size;
  runtime_.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(count, local)),
                                        cl::NDRange(local));
}

uint32_t WavefrontRenderer::read_count(const cl::Buffer& counter) {
  cl_uint value = 0;
  runtime_.queue().enqueueReadBuffer(counter, CL_TRUE, 0, sizeof value, &value);
  return value;
}

void WavefrontRenderer::write_count(const cl::Buffer& counter, uint32_t value) {
  cl_uint v = value;
  runtime_.queue().enqueueWriteBuffer(counter, CL_TRUE, 0, sizeof v, &v);
}

void WavefrontRenderer::bind_intersect(RayQueue& rays) {
  Buffers& b = *buffers_;
  set_args(intersect_, b.nodes, b.triangle_blocks, b.prim_refs, b.spheres, b.cylinders, b.triangles, rays.count,
           rays.origin, rays.dir, b.hits);
}

void WavefrontRenderer::bind_shade(const ShadeParams& params, RayQueue& in, RayQueue& next) {
  Buffers& b = *buffers_;
  set_args(shade_, b.spheres, b.cylinders, b.triangles, b.triangle_shading, b.materials, b.textures, b.texels,
           b.lights, params, in.count, in.origin, in.dir,
           in.weight, in.pixel, b.hits, b.film, next.count, next.origin, next.dir, next.weight, next.pixel,
           b.shadow.count, b.shadow.origin, b.shadow.dir, b.shadow.weight, b.shadow.pixel);
}

void WavefrontRenderer::bind_shadow() {
  Buffers& b = *buffers_;
  set_args(shadow_, b.nodes, b.triangle_blocks, b.prim_refs, b.spheres, b.cylinders, b.triangles, b.shadow.count,
           b.shadow.origin, b.shadow.dir, b.shadow.weight, b.shadow.pixel, b.film);
}

ShadeParams WavefrontRenderer::shade_params(cl_uint max_depth) const {
  ShadeParams params{};
  params.background = to_float4(scene_.background);
  params.ambient_light = to_float4(scene_.ambient_light.value_or(glm::vec3(1.0f)));
  params.mode = features_.mode == RenderMode::Binary ? RENDER_MODE_BINARY : RENDER_MODE_PHONG;
  params.light_count = features_.lights ? cl_uint(scene_.point_lights.size()) : 0;
  params.max_depth = max_depth;
  params.ray_capacity = cl_uint(buffers_->ray_capacity);
  params.shadow_capacity = cl_uint(buffers_->shadow_capacity);
  params.min_weight = settings_.min_weight;
  return params;
}

bool WavefrontRenderer::run_chunk(size_t first_pixel, size_t pixel_count, RenderStats* stats) {
  Buffers& b = *buffers_;
  auto& q = runtime_.queue();
  const CameraGPU cam = camera_for_chunk(first_pixel, pixel_count);

  RayQueue* current = &b.rays[0];
  RayQueue* next = &b.rays[1];
  set_args(generate_, cam, current->origin, current->dir, current->weight, current->pixel);
  launch(generate_, pixel_count);
  write_count(current->count, cl_uint(pixel_count));
  if (stats) stats->camera_rays += pixel_count;

  const ShadeParams params =
      shade_params(features_.secondary_rays() ? cl_uint(std::max(0, scene_.nbounces)) : 0);

  uint32_t ray_count = uint32_t(pixel_count);
  for (cl_uint depth = 0; ray_count > 0; ++depth) {
    bind_intersect(*current);
    launch(intersect_, ray_count);

    const bool spawns = features_.secondary_rays() && depth < params.max_depth;
    if (spawns) write_count(next->count, 0);
    if (features_.lights) write_count(b.shadow.count, 0);
    RayQueue& next_queue = spawns ? *next : b.rays[0];  // unused when nothing spawns (max_depth stops it)
    bind_shade(params, *current, next_queue);
    launch(shade_, ray_count);

    if (features_.lights) {
      const uint32_t shadow_count = read_count(b.shadow.count);
      if (shadow_count > b.shadow_capacity) return false;
      bind_shadow();
      launch(shadow_, shadow_count);
      if (stats) stats->shadow_rays += shadow_count;
    }
    if (!spawns) break;
    ray_count = read_count(next->count);
    if (ray_count > b.ray_capacity) return false;
    if (stats) stats->secondary_rays += ray_count;
    std::swap(current, next);
  }
  q.finish();
  return true;
}

void WavefrontRenderer::render_chunk(size_t first_pixel, size_t pixel_count, RenderStats* stats) {
  if (run_chunk(first_pixel, pixel_count, stats)) return;
  // A queue overflowed: undo this chunk's partial film and redo it in halves.
  if (pixel_count <= 1) throw Error("render: ray queue overflow on a single pixel (capacity too small)");
  const cl_ulong zero = 0;
  runtime_.queue().enqueueFillBuffer(buffers_->film, zero, first_pixel * 3 * sizeof(cl_ulong),
                                     pixel_count * 3 * sizeof(cl_ulong));
  if (stats) ++stats->chunk_retries;
  const size_t half = pixel_count / 2;
  render_chunk(first_pixel, half, stats);
  render_chunk(first_pixel + half, pixel_count - half, stats);
}

ImageF WavefrontRenderer::render(RenderStats* stats, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  Buffers& b = *buffers_;
  const size_t pixels = size_t(settings_.width) * settings_.height;
  try {
    const cl_ulong zero = 0;
    runtime_.queue().enqueueFillBuffer(b.film, zero, 0, pixels * 3 * sizeof(cl_ulong));
    for (size_t first = 0; first < pixels; first += b.chunk) {
      render_chunk(first, std::min(b.chunk, pixels - first), stats);
      if (progress) progress(std::min(pixels, first + b.chunk), pixels);
    }
    std::vector<cl_ulong> fixed(pixels * 3);
    runtime_.queue().enqueueReadBuffer(b.film, CL_TRUE, 0, fixed.size() * sizeof(cl_ulong), fixed.data());
    ImageF image;
    image.width = settings_.width;
    image.height = settings_.height;
    image.rgb.resize(fixed.size());
    for (size_t i = 0; i < fixed.size(); ++i) image.rgb[i] = float(double(fixed[i]) / FILM_FIXED_SCALE);
    if (stats) stats->render_ms = elapsed_ms(t0);
    return image;
  } catch (const cl::Error& e) {
    throw Error(std::string("render failed on ") + runtime_.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

double WavefrontRenderer::median_launch_ms(cl::Kernel& kernel, size_t count, int repetitions) {
  std::vector<double> times;
  launch(kernel, count);  // warm-up: PoCL compiles per local/global size on first use
  runtime_.queue().finish();
  for (int r = 0; r < std::max(1, repetitions); ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    launch(kernel, count);
    runtime_.queue().finish();
    times.push_back(elapsed_ms(t0));
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

double WavefrontRenderer::time_ray_kernel(cl::Kernel& kernel, const std::vector<cs_float4>& origin,
                                          const std::vector<cs_float4>& dir, size_t result_bytes, int repetitions,
                                          void* results) {
  if (origin.size() != dir.size()) throw Error("time_ray_kernel: origin and direction counts differ");
  if (origin.size() > 0xFFFFFFFFu) throw Error("time_ray_kernel: too many rays for one launch");
  const size_t n = origin.size();
  if (n == 0) return 0.0;
  Buffers& b = *buffers_;
  auto& ctx = runtime_.context();
  try {
    cl_uint count = cl_uint(n);
    cl::Buffer count_buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof count, &count);
    cl::Buffer origin_buffer = upload(ctx, origin);
    cl::Buffer dir_buffer = upload(ctx, dir);
    cl::Buffer result_buffer(ctx, CL_MEM_WRITE_ONLY, n * std::max<size_t>(1, result_bytes));
    set_args(kernel, b.nodes, b.triangle_blocks, b.prim_refs, b.spheres, b.cylinders, b.triangles, count_buffer,
             origin_buffer, dir_buffer, result_buffer);
    const double ms = median_launch_ms(kernel, n, repetitions);
    if (results) runtime_.queue().enqueueReadBuffer(result_buffer, CL_TRUE, 0, n * result_bytes, results);
    return ms;
  } catch (const cl::Error& e) {
    throw Error(std::string("ray batch timing failed on ") + runtime_.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

KernelTimings WavefrontRenderer::time_kernels(int repetitions) {
  Buffers& b = *buffers_;
  KernelTimings t;
  const size_t count = b.chunk;
  const CameraGPU cam = camera_for_chunk(0, count);
  RayQueue& rays = b.rays[0];
  set_args(generate_, cam, rays.origin, rays.dir, rays.weight, rays.pixel);
  launch(generate_, count);
  write_count(rays.count, cl_uint(count));

  auto median_ms = [&](cl::Kernel& k, size_t n) { return median_launch_ms(k, n, repetitions); };

  bind_intersect(rays);
  t.primary_rays = count;
  t.primary_ms = median_ms(intersect_, count);

  if (!features_.lights) return t;
  // Shade once (without spawning) to fill the shadow queue from these hits.
  const ShadeParams params = shade_params(0);
  write_count(b.shadow.count, 0);
  bind_shade(params, rays, rays);  // the next queue is never written: max_depth 0
  launch(shade_, count);
  const uint32_t shadow_count = std::min<uint32_t>(read_count(b.shadow.count), uint32_t(b.shadow_capacity));
  bind_shadow();
  t.shadow_rays = shadow_count;
  t.shadow_ms = median_ms(shadow_, shadow_count);
  return t;
}

}  // namespace caustica
