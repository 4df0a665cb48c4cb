#include "host/cl/runtime.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "host/cl/embedded_kernels.h"
#include "host/error.h"

namespace caustica {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
  size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "gpu";
  if (t & CL_DEVICE_TYPE_CPU) return "cpu";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

uint64_t fnv1a(const std::string& s, uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

// CAUSTICA_KERNEL_DIR (a kernels/ folder) replaces the embedded copies with
// the files there, read once: kernel work without relinking, and A/B timing
// of two kernel versions with one binary. The set of files stays the
// embedded one.
const std::map<std::string, const std::string*>& embedded_index() {
  static std::vector<std::string> overrides;
  static const std::map<std::string, const std::string*> index = [] {
    std::map<std::string, const std::string*> m;
    const char* dir = std::getenv("CAUSTICA_KERNEL_DIR");
    overrides.reserve(embedded_kernel_files().size());
    for (const auto& f : embedded_kernel_files()) {
      m[f.path] = &f.text;
      if (!dir || !*dir) continue;
      const std::string path = std::string(dir) + "/" + f.path;
      std::ifstream in(path, std::ios::binary);
      if (!in) throw Error("CAUSTICA_KERNEL_DIR: cannot read " + path);
      std::ostringstream text;
      text << in.rdbuf();
      overrides.push_back(text.str());
      m[f.path] = &overrides.back();
    }
    return m;
  }();
  return index;
}

// Inlines kernel includes from the embedded files, each file once per
// program. The preprocessor has not run yet: an #include inside a false
// #if is still inlined (and then compiled away), and marks the file as
// included; kernel files therefore keep their includes unconditional, or
// put conditional ones last (integrator_*.cl).
void expand_into(const std::string& name, const std::string& text, std::set<std::string>& included,
                 std::ostringstream& out) {
  out << "#line 1 \"" << name << "\"\n";
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::string t = trim(line);
    if (t.rfind("#include", 0) == 0) {
      size_t q0 = t.find('"');
      size_t q1 = q0 == std::string::npos ? q0 : t.find('"', q0 + 1);
      if (q0 != std::string::npos && q1 != std::string::npos) {
        std::string inc = t.substr(q0 + 1, q1 - q0 - 1);
        // Shared headers are written relative to the repository root for the
        // C++ side ("kernels/shared/types.h"); accept both spellings.
        if (inc.rfind("kernels/", 0) == 0) inc = inc.substr(8);
        const auto& index = embedded_index();
        auto it = index.find(inc);
        if (it == index.end())
          throw Error(name + ":" + std::to_string(line_no) + ": kernel include \"" + inc +
                      "\" is not an embedded kernel file (kernels/" + inc + ")");
        if (included.insert(inc).second) expand_into(inc, *it->second, included, out);
        out << "#line " << (line_no + 1) << " \"" << name << "\"\n";
        continue;
      }
    }
    out << line << '\n';
  }
}

std::string device_string(const cl::Device& d, cl_device_info what) {
  std::string s;
  d.getInfo(what, &s);
  return trim(s);
}

}  // namespace

std::string cl_error_name(cl_int code) {
  switch (code) {
    case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
    case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
    case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE";
    case CL_PLATFORM_NOT_FOUND_KHR: return "CL_PLATFORM_NOT_FOUND_KHR (no OpenCL driver installed)";
    default: return "OpenCL error " + std::to_string(code);
  }
}

std::string expand_kernel_source(const std::string& root_name, const std::string& root_text) {
  std::set<std::string> included{root_name};
  std::ostringstream out;
  expand_into(root_name, root_text, included, out);
  return out.str();
}

std::string map_build_log_lines(const std::string& log, const std::string& expanded_source) {
  // origin[i]: the file and line that physical line i + 1 came from.
  std::vector<std::pair<std::string, int>> origin;
  std::string file = "<kernel>";
  int next_line = 1;
  std::istringstream in(expanded_source);
  static const std::regex line_marker(R"re(^#line (\d+) "([^"]*)"\s*$)re");
  for (std::string line; std::getline(in, line);) {
    origin.emplace_back(file, next_line);
    std::smatch m;
    if (std::regex_match(line, m, line_marker)) {
      next_line = std::stoi(m[1]);
      file = m[2];
    } else {
      ++next_line;
    }
  }
  static const std::regex reference(R"re((<kernel>|<source>|input\.cl):(\d+))re");
  std::string out;
  auto last = log.cbegin();
  for (std::sregex_iterator it(log.begin(), log.end(), reference), end; it != end; ++it) {
    const auto& m = *it;
    out.append(last, m[0].first);
    const size_t physical = std::stoul(m[2]);
    if (physical >= 1 && physical <= origin.size())
      out += origin[physical - 1].first + ":" + std::to_string(origin[physical - 1].second);
    else
      out += m.str();
    last = m[0].second;
  }
  out.append(last, log.cend());
  return out;
}

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> result;
  std::vector<cl::Platform> platforms;
  cl_int err = cl::Platform::get(&platforms);
  if (err != CL_SUCCESS && err != CL_PLATFORM_NOT_FOUND_KHR)
    throw Error("cannot list OpenCL platforms: " + cl_error_name(err));
  for (size_t p = 0; p < platforms.size(); ++p) {
    std::vector<cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform without devices
    }
    std::string pname;
    platforms[p].getInfo(CL_PLATFORM_NAME, &pname);
    for (auto& d : devices) {
      DeviceInfo info;
      info.index = static_cast<int>(result.size());
      info.platform_index = static_cast<int>(p);
      info.platform_name = trim(pname);
      info.name = device_string(d, CL_DEVICE_NAME);
      info.vendor = device_string(d, CL_DEVICE_VENDOR);
      info.device_version = device_string(d, CL_DEVICE_VERSION);
      info.driver_version = device_string(d, CL_DRIVER_VERSION);
      info.type = type_name(d.getInfo<CL_DEVICE_TYPE>());
      info.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      info.global_mem_bytes = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
      info.max_alloc_bytes = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      info.correctly_rounded_divide_sqrt =
          (d.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
      info.device = d;
      result.push_back(info);
    }
  }
  return result;
}

DeviceInfo select_device(const std::string& requested) {
  std::string spec = requested;
  if (spec.empty()) {
    if (const char* env = std::getenv("CAUSTICA_DEVICE")) spec = env;
  }
  auto devices = list_devices();
  if (devices.empty())
    throw Error("no OpenCL device found: install an OpenCL driver (Debian: apt-get install pocl-opencl-icd)");
  auto listing = [&] {
    std::string s = "available devices:";
    for (auto& d : devices) s += "\n  [" + std::to_string(d.index) + "] " + d.type + "  " + d.name + "  (" + d.platform_name + ")";
    return s;
  };
  std::string s = lower(trim(spec));
  // Checking simulators (Oclgrind reports itself as a GPU) run kernels
  // thousands of times slower: they are picked by name, never by default.
  auto simulator = [](const DeviceInfo& d) { return lower(d.platform_name).find("oclgrind") != std::string::npos; };
  if (s.empty()) {
    for (auto& d : devices)
      if (d.type == "gpu" && !simulator(d)) return d;
    for (auto& d : devices)
      if (d.type == "cpu" && !simulator(d)) return d;
    for (auto& d : devices)
      if (!simulator(d)) return d;
    return devices.front();
  }
  if (std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); })) {
    size_t idx = std::stoul(s);
    if (idx < devices.size()) return devices[idx];
    throw Error("--device " + spec + ": no device with that index; " + listing());
  }
  if (s == "cpu" || s == "gpu") {
    for (auto& d : devices)
      if (d.type == s && !simulator(d)) return d;
    throw Error("--device " + spec + ": no " + s + " device; " + listing());
  }
  for (auto& d : devices)
    if (lower(d.name).find(s) != std::string::npos || lower(d.platform_name).find(s) != std::string::npos) return d;
  throw Error("--device " + spec + ": no device name or platform contains \"" + spec + "\"; " + listing());
}

Runtime::Runtime(const DeviceInfo& device, bool profiling)
    : info_(device), profiling_(profiling), simulator_(info_.platform_name.find("Oclgrind") != std::string::npos) {
  try {
    context_ = cl::Context(info_.device);
    queue_ = cl::CommandQueue(context_, info_.device, profiling ? CL_QUEUE_PROFILING_ENABLE : 0);
  } catch (const cl::Error& e) {
    throw Error("cannot create an OpenCL context on " + info_.name + ": " + e.what() + " (" + cl_error_name(e.err()) + ")");
  }
}

std::string Runtime::cache_directory() {
  if (const char* env = std::getenv("CAUSTICA_CACHE_DIR")) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME")) return std::string(xdg) + "/caustica";
  if (const char* home = std::getenv("HOME")) return std::string(home) + "/.cache/caustica";
  return "/tmp/caustica-cache";
}

void Runtime::fill(const cl::Buffer& buffer, const void* pattern, size_t pattern_size, size_t offset, size_t size) {
  if (size == 0) return;
  if (!simulator_) {
    const cl_int err = clEnqueueFillBuffer(queue_(), buffer(), pattern, pattern_size, offset, size, 0, nullptr, nullptr);
    if (err != CL_SUCCESS) throw cl::Error(err, "clEnqueueFillBuffer");
    return;
  }
  if (pattern_size % 4 || offset % 4 || size % 4 || size / 4 > UINT32_MAX)
    throw Error("Runtime::fill on a simulator needs whole 32-bit words");
  build_word_kernels();
  cl::Buffer words(context_, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, pattern_size, const_cast<void*>(pattern));
  const cl_uint count = cl_uint(size / 4);
  fill_words_.setArg(0, buffer);
  fill_words_.setArg(1, words);
  fill_words_.setArg(2, cl_uint(pattern_size / 4));
  fill_words_.setArg(3, cl_uint(offset / 4));
  fill_words_.setArg(4, count);
  queue_.enqueueNDRangeKernel(fill_words_, cl::NullRange, cl::NDRange(round_up(count, 64)), cl::NDRange(64));
}

void Runtime::copy(const cl::Buffer& src, const cl::Buffer& dst, size_t src_offset, size_t dst_offset, size_t size) {
  if (size == 0) return;
  if (!simulator_) {
    queue_.enqueueCopyBuffer(src, dst, src_offset, dst_offset, size);
    return;
  }
  if (src_offset % 4 || dst_offset % 4 || size % 4 || size / 4 > UINT32_MAX)
    throw Error("Runtime::copy on a simulator needs whole 32-bit words");
  build_word_kernels();
  const cl_uint count = cl_uint(size / 4);
  copy_words_.setArg(0, dst);
  copy_words_.setArg(1, cl_uint(dst_offset / 4));
  copy_words_.setArg(2, src);
  copy_words_.setArg(3, cl_uint(src_offset / 4));
  copy_words_.setArg(4, count);
  queue_.enqueueNDRangeKernel(copy_words_, cl::NullRange, cl::NDRange(round_up(count, 64)), cl::NDRange(64));
}

void Runtime::build_word_kernels() {
  if (fill_words_()) return;
  static const char* source = R"(
__kernel void fill_words(__global uint* dst, __global const uint* pattern, uint pattern_words, uint first, uint count) {
  const uint i = get_global_id(0);
  if (i < count) dst[first + i] = pattern[i % pattern_words];
}
__kernel void copy_words(__global uint* dst, uint dst_first, __global const uint* src, uint src_first, uint count) {
  const uint i = get_global_id(0);
  if (i < count) dst[dst_first + i] = src[src_first + i];
}
)";
  const cl::Program program = build_source("word_kernels.cl", source, "").program;
  fill_words_ = cl::Kernel(program, "fill_words");
  copy_words_ = cl::Kernel(program, "copy_words");
}

BuiltProgram Runtime::build_file(const std::string& path, const std::string& options) {
  const auto& index = embedded_index();
  auto it = index.find(path);
  if (it == index.end()) throw Error("kernel file \"" + path + "\" is not embedded in this binary");
  return build_source(path, *it->second, options);
}

BuiltProgram Runtime::build_source(const std::string& name, const std::string& text, const std::string& raw_options) {
  const std::string source = expand_kernel_source(name, text);
  // CPU devices share one address space for all OpenCL memory, which lets
  // the traversal issue real prefetches (kernels/lib/bvh_traverse.h).
  // Oclgrind (a checking simulator, --device oclgrind) builds with
  // -cl-opt-disable: its LLVM cannot run every intrinsic an optimising clang
  // emits, and the kernels then fail to appear (CL_INVALID_KERNEL_NAME).
  // Division and sqrt are asked to round correctly where the device can:
  // OpenCL's default allows 2.5 and 3 ulp (NVIDIA's driver uses that), while
  // the error-bounded ray origins count on IEEE rounding. Not with
  // -cl-fast-relaxed-math, which asks for approximations anyway, and whose
  // traversal NVIDIA's compiler (driver 580) gets wrong with both flags.
  // CAUSTICA_EXTRA_KERNEL_OPTIONS: appended to every build (a developer knob).
  const char* extra = std::getenv("CAUSTICA_EXTRA_KERNEL_OPTIONS");
  const bool oclgrind = simulator_;
  const bool fast_math = (raw_options + (extra ? extra : "")).find("-cl-fast-relaxed-math") != std::string::npos;
  const std::string options = "-cl-std=CL1.2 -cl-kernel-arg-info " +
                              std::string(info_.type == "cpu" ? "-DCAUSTICA_CPU_PREFETCH " : "") +
                              std::string(info_.correctly_rounded_divide_sqrt && !oclgrind && !fast_math
                                              ? "-cl-fp32-correctly-rounded-divide-sqrt "
                                              : "") +
                              raw_options +
                              (oclgrind ? " -cl-opt-disable" : "") + (extra ? std::string(" ") + extra : std::string());
  auto t0 = std::chrono::steady_clock::now();
  BuiltProgram built;

  uint64_t key = fnv1a(source);
  key = fnv1a(options, key);
  key = fnv1a(info_.platform_name + "|" + info_.name + "|" + info_.driver_version + "|" + info_.device_version, key);
  char key_hex[17];
  std::snprintf(key_hex, sizeof key_hex, "%016llx", static_cast<unsigned long long>(key));
  const std::filesystem::path cache_file = std::filesystem::path(cache_directory()) / (std::string(key_hex) + ".bin");

  if (cache_enabled_) {
    std::ifstream in(cache_file, std::ios::binary);
    if (in) {
      std::vector<unsigned char> binary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      try {
        cl::Program::Binaries binaries{binary};
        cl::Program program(context_, {info_.device}, binaries);
        program.build({info_.device}, options.c_str());
        built.program = program;
        built.from_cache = true;
      } catch (const cl::Error&) {
        built.from_cache = false;  // stale or foreign binary: rebuild below
      }
    }
  }
  if (!built.from_cache) {
    cl::Program program(context_, source);
    try {
      program.build({info_.device}, options.c_str());
    } catch (const cl::Error&) {
      std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
      throw Error("OpenCL kernel build failed for " + name + " on " + info_.name + " with options [" + options +
                  "]:\n" + map_build_log_lines(log, source));
    }
    built.program = program;
    if (cache_enabled_) {
      try {
        auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
        if (!binaries.empty() && !binaries[0].empty()) {
          std::error_code ec;
          std::filesystem::create_directories(cache_file.parent_path(), ec);
          const auto tmp = cache_file.string() + ".tmp" + std::to_string(std::rand());
          std::ofstream out(tmp, std::ios::binary);
          out.write(reinterpret_cast<const char*>(binaries[0].data()), static_cast<std::streamsize>(binaries[0].size()));
          out.close();
          std::filesystem::rename(tmp, cache_file, ec);  // atomic publish; concurrent writers are harmless
        }
      } catch (const std::exception&) {
        // A cache that cannot be written only costs the next run a cold build.
      }
    }
  }
  built.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return built;
}

}  // namespace caustica
