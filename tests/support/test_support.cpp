#include <sys/wait.h>

#include "tests/support/test_support.h"

#include <gtest/gtest.h>

#include "host/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <unistd.h>

namespace caustica::test {

namespace {

// Removes the directories temp_dir() created during a test when that test
// ends (and those created outside any test when the program ends), unless the
// test failed and CAUSTICA_KEEP_TEST_FILES is set.
class TempDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  // True when `dir` is new to this test (so it may hold a previous run's files).
  bool add(const std::filesystem::path& dir) {
    std::lock_guard<std::mutex> lock(mutex_);
    return dirs_.insert(dir).second;
  }
  void OnTestEnd(const ::testing::TestInfo& info) override { clean(info.result()->Failed()); }
  void OnTestProgramEnd(const ::testing::UnitTest& unit) override { clean(unit.Failed()); }

 private:
  void clean(bool failed) {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool keep = failed && std::getenv("CAUSTICA_KEEP_TEST_FILES") != nullptr;
    for (const auto& dir : dirs_) {
      if (keep) {
        std::cerr << "CAUSTICA_KEEP_TEST_FILES: kept " << dir.string() << "\n";
        continue;
      }
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
      if (ec) std::cerr << "could not remove " << dir.string() << ": " << ec.message() << "\n";
    }
    dirs_.clear();
  }

  std::mutex mutex_;
  std::set<std::filesystem::path> dirs_;
};

// Registered with gtest once, on first use; gtest owns and deletes it.
TempDirCleaner& temp_dir_cleaner() {
  static TempDirCleaner* cleaner = [] {
    auto* c = new TempDirCleaner;
    ::testing::UnitTest::GetInstance()->listeners().Append(c);
    return c;
  }();
  return *cleaner;
}

const char* const kTestKernelDir = "tests/kernels/";

std::string read_test_kernel(const std::string& name) {
  const std::string path = std::string(CAUSTICA_SOURCE_DIR) + "/" + name;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("test kernel " + path + " cannot be read (tests/kernels/ of the source tree)");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every file of tests/kernels/, by the path an #include names it with.
const KernelFiles& test_kernel_files() {
  static const KernelFiles files = [] {
    KernelFiles f;
    const std::filesystem::path root = std::filesystem::path(CAUSTICA_SOURCE_DIR) / kTestKernelDir;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
      if (entry.is_regular_file()) {
        const std::string name = kTestKernelDir + std::filesystem::relative(entry.path(), root).generic_string();
        f[name] = read_test_kernel(name);
      }
    return f;
  }();
  return files;
}

}  // namespace

std::string write_scene(const std::string& name, const std::string& text) {
  const std::string path = temp_dir() + "/" + name;
  std::ofstream out(path);
  out << text;
  if (!out) throw Error("cannot write " + path);
  return path;
}

std::string test_kernel_source(const std::string& relative_path) { return read_test_kernel(kTestKernelDir + relative_path); }

BuiltProgram build_test_kernel(const std::string& relative_path, const std::string& options, Runtime& rt) {
  return rt.build_source(kTestKernelDir + relative_path, test_kernel_source(relative_path), options,
                         &test_kernel_files());
}

std::string device_spec() {
  const char* env = std::getenv("CAUSTICA_TEST_DEVICE");
  return env ? env : "cpu";
}

void expect_finite_render(const ImageF& image, const FilmCounts& film, const std::string& what) {
  size_t nonfinite = 0;
  for (float v : image.rgb) nonfinite += !std::isfinite(v);
  EXPECT_EQ(nonfinite, 0u) << what << ": NaN/Inf values in the image";
  EXPECT_EQ(film.nonfinite, 0u) << what << ": non-finite samples reached the film";
  EXPECT_EQ(film.negative, 0u) << what << ": negative samples reached the film";
}

bool on_simulator() {
  const char* simulated = std::getenv("CAUSTICA_TEST_SIMULATED_SIZES");
  if (simulated && std::string(simulated) == "1") return true;
  return runtime().device_info().platform_name.find("Oclgrind") != std::string::npos;
}

Runtime& runtime() {
  // Never destroyed: released at exit, after the OpenCL implementation's own
  // statics may be gone, its objects corrupt Oclgrind's heap ("corrupted
  // double-linked list"). The tests' static programs are leaked alike.
  static Runtime* rt = new Runtime(select_device(device_spec()));
  return *rt;
}

std::string source_dir() { return CAUSTICA_SOURCE_DIR; }

std::vector<std::string> committed_path_scenes() {
  std::vector<std::string> scenes;
  for (const auto& e : std::filesystem::directory_iterator(source_dir() + "/scenes")) {
    if (e.path().extension() != ".json") continue;
    const std::string text = slurp(e.path().string());
    const size_t mode = text.find("\"rendermode\"");
    if (mode != std::string::npos && text.find("path", mode) < text.find('\n', mode))
      scenes.push_back(e.path().string());
  }
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

std::string shared_dir() {
  std::filesystem::path p;
  if (const char* env = std::getenv("CAUSTICA_SHARED_DIR"))
    p = env;
  else
    p = std::filesystem::path(CAUSTICA_SOURCE_DIR) / ".." / "shared";
  std::error_code ec;
  if (!std::filesystem::is_directory(p, ec)) return {};
  return std::filesystem::weakly_canonical(p, ec).string();
}

std::string binary_path() { return CAUSTICA_BINARY; }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected caustica::Error, got std::exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected caustica::Error, nothing was thrown";
  return {};
}

// Under coreutils' timeout: a caustica that hangs fails its test after
// kCliTimeoutSeconds (status 124) and is killed, rather than running on
// after ctest gives up on the test process. A caustica killed by a signal
// still reads as signalled (timeout exits with 128 + the signal, as the
// shell does).
constexpr int kCliTimeoutSeconds = 300;

CliResult run_cli(const std::string& args) {
  const std::string cmd = "timeout --kill-after=10 " + std::to_string(kCliTimeoutSeconds) + " " + binary_path() +
                          " " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  const int status = pclose(p);
  r.signalled = WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) > 128);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (r.status == 124) r.output += "\n[run_cli] timed out after " + std::to_string(kCliTimeoutSeconds) + " s: " + args;
  return r;
}

std::string temp_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "caustica";
  for (auto& c : name)
    if (c == '/') c = '_';
  auto dir = std::filesystem::temp_directory_path() / ("caustica_test_" + std::to_string(::getpid()) + "_" + name);
  std::error_code ec;
  if (temp_dir_cleaner().add(dir)) std::filesystem::remove_all(dir, ec);  // left by an earlier run with this pid
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace caustica::test
