#include "host/bench/ray_batch.h"

#include <algorithm>
#include <chrono>

#include "host/error.h"
#include "host/render/kernel_args.h"

namespace caustica {

double time_ray_kernel(Runtime& runtime, const DeviceScene& scene, StageKernel& kernel, const char* result_name,
                       const std::vector<cs_float4>& origin, const std::vector<cs_float4>& dir, size_t result_bytes,
                       int repetitions, void* results, size_t local_size) {
  if (origin.size() != dir.size()) throw Error("time_ray_kernel: origin and direction counts differ");
  if (origin.size() > 0xFFFFFFFFu) throw Error("time_ray_kernel: too many rays for one launch");
  const size_t n = origin.size();
  if (n == 0) return 0.0;
  auto& ctx = runtime.context();
  auto& queue = runtime.queue();
  try {
    const std::vector<cl_uint> count{cl_uint(n)};
    // Held here: a kernel argument does not keep its buffer alive.
    const cl::Buffer count_buffer = upload_buffer(ctx, count), origin_buffer = upload_buffer(ctx, origin),
                     dir_buffer = upload_buffer(ctx, dir);
    cl::Buffer result_buffer(ctx, CL_MEM_WRITE_ONLY, n * std::max<size_t>(1, result_bytes));
    KernelArgs args(kernel);
    scene.bind_geometry(args)
        .arg("rays_count", count_buffer)
        .arg("rays_origin", origin_buffer)
        .arg("rays_dir", dir_buffer)
        .arg(result_name, result_buffer)
        .finish();
    const cl::NDRange global(round_up(n, local_size)), local(local_size);
    queue.enqueueNDRangeKernel(kernel.kernel, cl::NullRange, global, local);  // warm-up
    queue.finish();
    std::vector<double> times;
    for (int r = 0; r < std::max(1, repetitions); ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      queue.enqueueNDRangeKernel(kernel.kernel, cl::NullRange, global, local);
      queue.finish();
      times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    if (results) queue.enqueueReadBuffer(result_buffer, CL_TRUE, 0, n * result_bytes, results);
    return times[times.size() / 2];
  } catch (const cl::Error& e) {
    throw Error(std::string("ray batch timing failed on ") + runtime.device_info().name + ": " + e.what() + " (" +
                cl_error_name(e.err()) + ")");
  }
}

}  // namespace caustica
