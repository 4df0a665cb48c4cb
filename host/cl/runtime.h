// OpenCL plumbing: device listing and portable selection, a context + queue,
// and program builds from the embedded kernel sources with an on-disk cache of
// built binaries keyed by (source hash, options, device, driver).
#pragma once

#include <CL/opencl.hpp>
#include <map>
#include <memory>

#include <string>
#include <vector>

namespace caustica {

struct DeviceInfo {
  int index = -1;  // position in list_devices(), across all platforms
  int platform_index = -1;
  std::string platform_name;
  std::string name;
  std::string vendor;
  std::string type;  // "cpu", "gpu", "accelerator", "other"
  std::string device_version;
  std::string driver_version;
  unsigned compute_units = 0;
  size_t global_mem_bytes = 0;
  size_t max_alloc_bytes = 0;  // CL_DEVICE_MAX_MEM_ALLOC_SIZE: the largest single buffer
  // CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT: the device can build with
  // -cl-fp32-correctly-rounded-divide-sqrt (Runtime::build_source asks for it).
  bool correctly_rounded_divide_sqrt = false;
  cl::Device device;
};

std::vector<DeviceInfo> list_devices();

// spec: "" (then $CAUSTICA_DEVICE, then the default: first GPU, else first
// CPU, else device 0), a decimal index, "cpu", "gpu", or a case-insensitive
// substring of the device or platform name. Throws caustica::Error listing
// the available devices when nothing matches.
DeviceInfo select_device(const std::string& spec);

struct BuiltProgram {
  cl::Program program;
  double build_ms = 0.0;  // wall time of compile (cold) or cache load + link (warm)
  bool from_cache = false;
  // Built from source by a platform that keeps its own program cache
  // (PoCL): cold or from that cache, which this process cannot tell apart.
  bool platform_cache = false;
  // "cached", "cold", or "cold or from PoCL's cache": what -v and reports say.
  const char* cache_state() const {
    return from_cache ? "cached" : platform_cache ? "cold or from PoCL's cache" : "cold";
  }
};

// Expands `#include "..."` directives against the embedded kernel files
// (paths relative to kernels/), with #line markers so build logs point at the
// original file and line. Each inlined file carries a generated guard, so
// the preprocessor's #if decides which includes count (runtime.cpp,
// expand_into). `extra` adds files beyond the embedded ones, by the path
// their includes name (the tests' kernels: "tests/kernels/...").
using KernelFiles = std::map<std::string, std::string>;
std::string expand_kernel_source(const std::string& root_name, const std::string& root_text,
                                 const KernelFiles* extra = nullptr);

// A program's options with every feature flag of kernels/shared/
// feature_flags.h given a value: the flags named (-DHAS_X, -DHAS_X=0|1,
// -D HAS_X; the last one counts) keep theirs, the others get the table's
// default. The other options come first, in their order, then every flag as
// -DHAS_X=v in table order: two option strings that mean the same flags give
// the same string (and program cache key). Throws caustica::Error for a
// HAS_* name the table does not have or a value other than 0 or 1.
std::string complete_feature_flags(const std::string& options);

// Rewrites the line references of a build log that count physical lines of
// the expanded source ("<kernel>:330:10", "input.cl:312") as the original
// file and line the #line markers name ("broken.cl:3:10"). Compilers that
// honour #line (PoCL's clang) already write those; NVIDIA's and Oclgrind's
// do not.
std::string map_build_log_lines(const std::string& log, const std::string& expanded_source);

class Runtime {
 public:
  // profiling: the queue records kernel start/end times (caustica bench's
  // stage breakdown); off for renders, where it would only cost.
  explicit Runtime(const DeviceInfo& device, bool profiling = false);
  // The process's one runtime for this device and profiling choice, made on
  // first use and kept until the process ends (never destroyed: at exit the
  // OpenCL implementation's own statics may already be gone). Renders one
  // after another in one process (tests, a script's loop) share its context
  // and the programs it has built, instead of a context and a cache load
  // each.
  static std::shared_ptr<Runtime> shared(const DeviceInfo& device, bool profiling = false);
  bool profiling() const { return profiling_; }

  const DeviceInfo& device_info() const { return info_; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }

  // Builds an embedded kernel file (e.g. "integrator_phong.cl") with the given -D
  // options. Throws caustica::Error with the build log on failure.
  BuiltProgram build_file(const std::string& path, const std::string& options);
  // Builds source text that may #include embedded files, and `extra` ones
  // (used by tests).
  BuiltProgram build_source(const std::string& name, const std::string& text, const std::string& options,
                            const KernelFiles* extra = nullptr);

  // clEnqueueFillBuffer: `size` bytes of `buffer` from `offset` get `pattern`
  // repeated. On Oclgrind a kernel writes them instead: Oclgrind 21.10 marks
  // only the last pattern-sized store of a fill as initialised (its shadow
  // buffer is reallocated per host store), so its uninitialised-read check
  // would flag every filled buffer. Pattern size, offset and size must be
  // multiples of 4 bytes there.
  void fill(const cl::Buffer& buffer, const void* pattern, size_t pattern_size, size_t offset, size_t size);
  template <class T>
  void fill(const cl::Buffer& buffer, const T& pattern, size_t offset, size_t size) {
    fill(buffer, &pattern, sizeof(T), offset, size);
  }
  // clEnqueueCopyBuffer, by a kernel on Oclgrind for the same reason: a
  // copy into part of a buffer leaves Oclgrind 21.10 a shadow the size of the
  // copy, and every later read past it reports.
  void copy(const cl::Buffer& src, const cl::Buffer& dst, size_t src_offset, size_t dst_offset, size_t size);
  // The device is Oclgrind, a checking simulator.
  bool on_simulator() const { return simulator_; }

  // Disables the on-disk cache and the programs kept in memory (tests that
  // time or exercise cold builds).
  void set_cache_enabled(bool enabled) { cache_enabled_ = enabled; }
  static std::string cache_directory();

 private:
  DeviceInfo info_;
  cl::Context context_;
  cl::CommandQueue queue_;
  bool cache_enabled_ = true;
  // PoCL keeps the programs it builds in its own cache (POCL_CACHE_DIR,
  // keyed by source, options and device; unless POCL_KERNEL_CACHE=0): this
  // runtime then keeps no binaries of its own (build_source says why).
  bool platform_caches_programs_ = false;
  // Programs built in this process, by the cache key (source, options,
  // device): a second build of the same program is a lookup.
  std::map<uint64_t, cl::Program> built_;
  bool profiling_ = false;
  bool simulator_ = false;
  cl::Kernel fill_words_, copy_words_;  // built on first use on a simulator
  void build_word_kernels();
};

// Rounds n up to a multiple of the local size (PoCL picks local size 1 for
// awkward global sizes).
inline size_t round_up(size_t n, size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

std::string cl_error_name(cl_int code);

}  // namespace caustica
