#include "host/cl/runtime.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include "host/cl/embedded_kernels.h"
#include "host/error.h"
#include "kernels/shared/feature_flags.h"

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

// One line of a kernel file, as the include expander sees it.
struct ScannedLine {
  enum Kind { Code, Blank, Directive } kind = Blank;
  std::string directive;  // "if", "ifndef", "include", "line", ...
  std::string argument;   // the rest, without comments and white space
};

// Classifies the lines of a kernel file: preprocessor directives (outside
// block comments), lines with code, and blank or comment-only lines.
std::vector<ScannedLine> scan_lines(const std::vector<std::string>& lines) {
  std::vector<ScannedLine> out(lines.size());
  bool in_comment = false;
  for (size_t n = 0; n < lines.size(); ++n) {
    const std::string& line = lines[n];
    const bool starts_in_comment = in_comment;
    bool code = false;
    std::string uncommented;
    for (size_t i = 0; i < line.size(); ++i) {
      if (in_comment) {
        if (line.compare(i, 2, "*/") == 0) in_comment = false, ++i;
      } else if (line.compare(i, 2, "/*") == 0) {
        in_comment = true, ++i;
      } else if (line.compare(i, 2, "//") == 0) {
        break;
      } else if (!std::isspace(static_cast<unsigned char>(line[i]))) {
        code = true;
        uncommented += line[i];
      }
    }
    ScannedLine& s = out[n];
    if (!starts_in_comment && !uncommented.empty() && uncommented[0] == '#') {
      // uncommented has no white space: "#ifndef X" is "#ifndefX"; the
      // directive's name is read from the line itself.
      const std::string t = trim(line);
      size_t i = 1;
      while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
      size_t j = i;
      while (j < t.size() && std::isalpha(static_cast<unsigned char>(t[j]))) ++j;
      s.kind = ScannedLine::Directive;
      s.directive = t.substr(i, j - i);  // "include" also in #include"x"
      const size_t at = uncommented.find(s.directive);
      s.argument = at == std::string::npos ? "" : uncommented.substr(at + s.directive.size());
    } else {
      s.kind = code ? ScannedLine::Code : ScannedLine::Blank;
    }
  }
  return out;
}

bool opens_conditional(const ScannedLine& s) {
  return s.kind == ScannedLine::Directive && (s.directive == "if" || s.directive == "ifdef" || s.directive == "ifndef");
}
bool closes_conditional(const ScannedLine& s) { return s.kind == ScannedLine::Directive && s.directive == "endif"; }

// The lines of a classic include guard (#ifndef X / #define X ... #endif
// around everything but comments, blank lines and #line markers), as
// {open, close}; {-1, -1} when the file has none. The guard's condition is
// false only when the file was compiled before, so it does not make the
// file's includes conditional.
std::pair<int, int> include_guard(const std::vector<ScannedLine>& s) {
  const std::pair<int, int> none{-1, -1};
  int open = -1;
  for (int i = 0; i < int(s.size()); ++i) {
    if (s[i].kind == ScannedLine::Blank || (s[i].kind == ScannedLine::Directive && s[i].directive == "line")) continue;
    if (s[i].kind != ScannedLine::Directive || s[i].directive != "ifndef") return none;
    open = i;
    break;
  }
  if (open < 0) return none;
  int define = open + 1;
  while (define < int(s.size()) && s[define].kind == ScannedLine::Blank) ++define;
  if (define >= int(s.size()) || s[define].kind != ScannedLine::Directive || s[define].directive != "define" ||
      s[define].argument != s[open].argument)
    return none;
  int depth = 0;
  for (int i = open; i < int(s.size()); ++i) {
    if (opens_conditional(s[i])) ++depth;
    if (closes_conditional(s[i]) && --depth == 0) {
      for (int j = i + 1; j < int(s.size()); ++j)
        if (s[j].kind != ScannedLine::Blank) return none;
      return {open, i};
    }
  }
  return none;
}

// What the expander knows of an open conditional. It expands for OpenCL C
// only, so a test of __OPENCL_C_VERSION__ is known (the shared headers'
// `#ifdef __OPENCL_C_VERSION__ ... #else <C++ side> #endif`); any other
// condition is the preprocessor's to decide.
enum class Branch { Guard, Taken, Dead, Unknown };

Branch branch_of(const ScannedLine& s) {
  const std::string& a = s.argument;
  const bool opencl = a == "__OPENCL_C_VERSION__" || a == "defined(__OPENCL_C_VERSION__)" || a == "defined__OPENCL_C_VERSION__";
  const bool not_opencl = a == "!defined(__OPENCL_C_VERSION__)" || a == "!defined__OPENCL_C_VERSION__";
  if (s.directive == "ifdef") return a == "__OPENCL_C_VERSION__" ? Branch::Taken : Branch::Unknown;
  if (s.directive == "ifndef") return a == "__OPENCL_C_VERSION__" ? Branch::Dead : Branch::Unknown;
  if (opencl && a != "__OPENCL_C_VERSION__") return Branch::Taken;  // #if defined(...); a bare #if V is a number
  if (not_opencl) return Branch::Dead;
  return Branch::Unknown;
}

// The macro that guards an inlined kernel file: CS_INCLUDED_ and the path,
// every character but letters and digits written as _ and its hex code.
std::string inline_guard(const std::string& path) {
  std::string g = "CS_INCLUDED_";
  for (unsigned char c : path) {
    if (std::isalnum(c)) {
      g += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "_%02X", c);
      g += hex;
    }
  }
  return g;
}

struct ExpandState {
  const KernelFiles* extra = nullptr;   // files beyond the embedded ones
  std::set<std::string> unconditional;  // inlined at a site no #if encloses: compiled by the time it is passed
  std::vector<std::string> stack;       // files being inlined (their guards are defined already)
};

// Inlines kernel includes from the embedded files. The preprocessor has not
// run yet, so the real one decides: every inlined file is wrapped in its own
// guard (#ifndef CS_INCLUDED_<path> / #define ... / #endif), and a file is
// inlined again at each include site until one that no #if / #ifdef /
// #ifndef encloses (counting the enclosing files' sites; a file's own
// include guard and a taken #ifdef __OPENCL_C_VERSION__ do not count); after
// that site the file has been compiled, and later includes of it are
// dropped. An #include inside a false #if therefore costs nothing and hides
// nothing from later includes. Includes in the C++ side of a shared header
// (the #else of #ifdef __OPENCL_C_VERSION__) are dropped. #line markers keep
// every line at its original file and line (build logs,
// map_build_log_lines).
void expand_into(const std::string& name, const std::string& text, int site_depth, ExpandState& state,
                 std::ostringstream& out) {
  out << "#line 1 \"" << name << "\"\n";
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  const std::vector<ScannedLine> scanned = scan_lines(lines);
  const std::pair<int, int> guard = include_guard(scanned);
  std::vector<Branch> open;  // this file's open conditionals
  state.stack.push_back(name);
  for (size_t n = 0; n < lines.size(); ++n) {
    const std::string& line = lines[n];
    const ScannedLine& s = scanned[n];
    const int line_no = int(n) + 1;
    if (opens_conditional(s)) {
      open.push_back(int(n) == guard.first ? Branch::Guard : branch_of(s));
    } else if (closes_conditional(s)) {
      if (!open.empty()) open.pop_back();
    } else if (s.kind == ScannedLine::Directive && (s.directive == "else" || s.directive == "elif") && !open.empty()) {
      Branch& b = open.back();
      if (b == Branch::Taken) b = Branch::Dead;
      else if (b == Branch::Dead) b = s.directive == "else" ? Branch::Taken : Branch::Unknown;
      else b = Branch::Unknown;
    }
    const std::string t = trim(line);
    if (s.kind == ScannedLine::Directive && s.directive == "include") {
      size_t q0 = t.find('"');
      size_t q1 = q0 == std::string::npos ? q0 : t.find('"', q0 + 1);
      if (q0 != std::string::npos && q1 != std::string::npos) {
        const bool dead = std::count(open.begin(), open.end(), Branch::Dead) > 0;
        const int depth = site_depth + int(std::count(open.begin(), open.end(), Branch::Unknown));
        std::string inc = t.substr(q0 + 1, q1 - q0 - 1);
        // Shared headers are written relative to the repository root for the
        // C++ side ("kernels/shared/types.h"); accept both spellings.
        if (inc.rfind("kernels/", 0) == 0) inc = inc.substr(8);
        const auto& index = embedded_index();
        auto it = index.find(inc);
        const std::string* included_text = it != index.end() ? it->second : nullptr;
        if (!included_text && state.extra) {
          auto e = state.extra->find(inc);
          if (e != state.extra->end()) included_text = &e->second;
        }
        if (!included_text && !dead)
          throw Error(name + ":" + std::to_string(line_no) + ": kernel include \"" + inc +
                      "\" is not an embedded kernel file (kernels/" + inc + ")");
        const bool on_stack = std::find(state.stack.begin(), state.stack.end(), inc) != state.stack.end();
        if (!dead && !on_stack && !state.unconditional.count(inc)) {
          if (depth == 0) state.unconditional.insert(inc);
          const std::string g = inline_guard(inc);
          // The first marker names the guard's lines (as the include's
          // first lines); the second restarts the file at line 1.
          out << "#line 1 \"" << inc << "\"\n#ifndef " << g << "\n#define " << g << "\n";
          expand_into(inc, *included_text, depth, state, out);
          out << "#endif /* " << g << " */\n";
        }
        out << "#line " << (line_no + 1) << " \"" << name << "\"\n";
        continue;
      }
    }
    out << line << '\n';
  }
  state.stack.pop_back();
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

std::string expand_kernel_source(const std::string& root_name, const std::string& root_text, const KernelFiles* extra) {
  ExpandState state;
  state.extra = extra;
  state.unconditional.insert(root_name);
  std::ostringstream out;
  expand_into(root_name, root_text, 0, state, out);
  return out.str();
}

std::string complete_feature_flags(const std::string& options) {
  std::vector<std::string> tokens, others;
  {
    std::istringstream in(options);
    for (std::string t; in >> t;) tokens.push_back(t);
  }
  std::vector<std::string> value(kFeatureFlagCount);
  for (size_t i = 0; i < tokens.size(); ++i) {
    std::string definition;
    size_t used = 1;
    if (tokens[i] == "-D" && i + 1 < tokens.size()) {
      definition = tokens[i + 1];
      used = 2;
    } else if (tokens[i].rfind("-D", 0) == 0) {
      definition = tokens[i].substr(2);
    }
    const size_t eq = definition.find('=');
    const std::string name = definition.substr(0, eq);
    const std::string v = eq == std::string::npos ? "1" : definition.substr(eq + 1);
    int flag = -1;
    for (int f = 0; f < kFeatureFlagCount; ++f)
      if (name == kFeatureFlags[f].name) flag = f;
    if (flag < 0 && name.rfind("HAS_", 0) == 0)
      throw Error("kernel option -D" + definition + ": " + name +
                  " is not a feature flag (kernels/shared/feature_flags.h lists them)");
    if (flag < 0) {
      for (size_t k = 0; k < used; ++k) others.push_back(tokens[i + k]);
    } else if (v != "0" && v != "1") {
      throw Error("kernel option -D" + definition + ": a feature flag is 0 or 1");
    } else {
      value[flag] = v;
    }
    i += used - 1;
  }
  std::string out;
  for (const auto& t : others) out += (out.empty() ? "" : " ") + t;
  for (int f = 0; f < kFeatureFlagCount; ++f)
    out += std::string(out.empty() ? "" : " ") + "-D" + kFeatureFlags[f].name + "=" +
           (value[f].empty() ? std::to_string(kFeatureFlags[f].default_value) : value[f]);
  return out;
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
  const char* pocl_cache = std::getenv("POCL_KERNEL_CACHE");
  platform_caches_programs_ = info_.platform_name.find("Portable Computing Language") != std::string::npos &&
                              !(pocl_cache && std::string(pocl_cache) == "0");
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

BuiltProgram Runtime::build_source(const std::string& name, const std::string& text, const std::string& raw_options,
                                   const KernelFiles* extra_files) {
  const std::string source = expand_kernel_source(name, text, extra_files);
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
  // Every feature flag gets a value (complete_feature_flags): the kernels
  // test them with #if, and the cache key below sees each flag once, in
  // table order.
  const char* extra = std::getenv("CAUSTICA_EXTRA_KERNEL_OPTIONS");
  const bool oclgrind = simulator_;
  const bool fast_math = (raw_options + (extra ? extra : "")).find("-cl-fast-relaxed-math") != std::string::npos;
  const std::string options = "-cl-std=CL1.2 -cl-kernel-arg-info " +
                              std::string(info_.type == "cpu" ? "-DCAUSTICA_CPU_PREFETCH " : "") +
                              std::string(info_.correctly_rounded_divide_sqrt && !oclgrind && !fast_math
                                              ? "-cl-fp32-correctly-rounded-divide-sqrt "
                                              : "") +
                              complete_feature_flags(raw_options + (extra ? std::string(" ") + extra : std::string())) +
                              (oclgrind ? " -cl-opt-disable" : "");
  auto t0 = std::chrono::steady_clock::now();
  BuiltProgram built;

  uint64_t key = fnv1a(source);
  key = fnv1a(options, key);
  key = fnv1a(info_.platform_name + "|" + info_.name + "|" + info_.driver_version + "|" + info_.device_version, key);
  char key_hex[17];
  std::snprintf(key_hex, sizeof key_hex, "%016llx", static_cast<unsigned long long>(key));
  const std::filesystem::path cache_file = std::filesystem::path(cache_directory()) / (std::string(key_hex) + ".bin");

  if (cache_enabled_) {
    if (auto it = built_.find(key); it != built_.end()) {
      built.program = it->second;
      built.from_cache = true;
      built.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      return built;
    }
  }
  // On PoCL the on-disk cache is PoCL's own: asking PoCL for a program's
  // binary (CL_PROGRAM_BINARIES) makes it compile every kernel once more,
  // for a work-group size left open (its "0-0-0" variants), before the
  // sizes the launches use, for a binary PoCL's cache would have served
  // anyway (issue 44: the Cornell box's cold build 3.6-3.8 s -> 1.2-1.4 s;
  // the test suite builds 185 programs cold). Elsewhere (NVIDIA, Oclgrind)
  // the binary is kept here. A build that must be cold (the cache disabled:
  // --no-cache, caustica bench) defines a macro PoCL's cache has never seen
  // (its key reads the options; a comment in the source would not do: it
  // hashes the preprocessed text).
  const bool disk_cache = cache_enabled_ && !platform_caches_programs_;
  built.platform_cache = platform_caches_programs_ && cache_enabled_;
  std::string build_options = options;
  if (platform_caches_programs_ && !cache_enabled_) {
    static std::atomic<uint64_t> cold_builds{0};
    build_options += " -DCAUSTICA_COLD_BUILD=" + std::to_string(uint64_t(getpid())) + "_" +
                     std::to_string(cold_builds++) + "_" +
                     std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  }
  if (disk_cache) {
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
      program.build({info_.device}, build_options.c_str());
    } catch (const cl::Error&) {
      std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
      throw Error("OpenCL kernel build failed for " + name + " on " + info_.name + " with options [" + options +
                  "]:\n" + map_build_log_lines(log, source));
    }
    built.program = program;
    if (disk_cache) {
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
  if (cache_enabled_) built_[key] = built.program;
  built.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return built;
}

std::shared_ptr<Runtime> Runtime::shared(const DeviceInfo& device, bool profiling) {
  static std::mutex guard;
  static auto* runtimes = new std::map<std::string, std::shared_ptr<Runtime>>();  // never destroyed (above)
  const std::string key = std::to_string(device.index) + "|" + device.platform_name + "|" + device.name + "|" +
                          (profiling ? "profiling" : "");
  std::lock_guard<std::mutex> lock(guard);
  std::shared_ptr<Runtime>& runtime = (*runtimes)[key];
  if (!runtime) runtime = std::make_shared<Runtime>(device, profiling);
  return runtime;
}

}  // namespace caustica
