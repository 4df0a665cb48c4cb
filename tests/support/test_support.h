// Helpers shared by the test executables: one OpenCL runtime on the test
// device (PoCL's CPU device unless CAUSTICA_TEST_DEVICE says otherwise), the
// test kernels of tests/kernels/, paths to the repository and to ../shared
// (tests that need it skip when absent).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <initializer_list>
#include <functional>
#include <string>

#include "host/cl/runtime.h"
#include "host/image/image.h"
#include "host/render/film.h"

namespace caustica::test {

Runtime& runtime();
// The device spec of runtime(): $CAUSTICA_TEST_DEVICE, else "cpu"; renders
// through a Session use it too, so the whole suite can run on one device
// (another OpenCL platform, or oclgrind's simulator).
std::string device_spec();
// True when the test device is a checking simulator (Oclgrind), which
// interprets every work-item about a thousand times slower than PoCL; also
// on any device under CAUSTICA_TEST_SIMULATED_SIZES=1, to check in seconds
// on PoCL that the assertions hold at the simulator's sizes.
bool on_simulator();
// `full` on a real device, `simulated` on a simulator: tests that trace
// millions of rays or samples keep their assertions there with fewer of
// them. Each call site says what it cuts.
inline size_t sized(size_t full, size_t simulated) { return on_simulator() ? simulated : full; }
std::string source_dir();

// The test kernels live in tests/kernels/ (read from the source tree when a
// test runs, not embedded): test_kernel_source("stiff/grazing.cl") is the
// text of tests/kernels/stiff/grazing.cl. Throws caustica::Error naming the
// path of a file that cannot be read.
std::string test_kernel_source(const std::string& relative_path);
// Builds test_kernel_source(relative_path) on `rt` with `options`; the
// program (and its build log) is named "tests/kernels/<relative_path>".
// The runtime's expander resolves its includes, among the embedded kernel
// files ("lib/bvh_traverse.h") and the files of tests/kernels/
// ("tests/kernels/stiff/random.h").
BuiltProgram build_test_kernel(const std::string& relative_path, const std::string& options, Runtime& rt = runtime());
// "<repo>/../shared" or $CAUSTICA_SHARED_DIR; empty when it does not exist.
std::string shared_dir();
// The committed scenes (scenes/*.json) whose rendermode is path, sorted.
std::vector<std::string> committed_path_scenes();
std::string binary_path();  // the caustica executable

// The message of the caustica::Error that `fn` throws; fails the test if it
// throws nothing or something else.
std::string error_of(const std::function<void()>& fn);
// A file's bytes ("" when it cannot be read).
std::string slurp(const std::string& path);

// What running the caustica executable gave: its exit status, whether a
// signal ended it (the shell reports one as 128 + signal), stdout + stderr.
struct CliResult {
  bool signalled = false;
  int status = -1;
  std::string output;
};
// Runs `caustica ARGS` (a shell word list) through the shell, under a
// timeout: a hang ends with status 124 and a line saying so in the output.
CliResult run_cli(const std::string& args);
// A fresh temporary directory for this test,
// <tmp>/caustica_test_<pid>_<suite>_<test>: the same path on every call within
// one test, emptied on the first. It is removed with everything in it when the
// test ends (a listener that temp_dir() registers with gtest on first use),
// except when the test failed and the environment variable
// CAUSTICA_KEEP_TEST_FILES is set, to look at what it wrote. Called outside a
// test (no current test), the directory is <tmp>/caustica_test_<pid>_caustica
// and is removed when the program ends. Tests write files only under it.
std::string temp_dir();
// Writes `text` to temp_dir()/name; returns the path.
std::string write_scene(const std::string& name, const std::string& text);

// Every image the shared render helpers return (stiff::render,
// render_path) passes through here: no NaN or Inf pixel, and no non-finite
// or negative sample reached the film (which drops and counts them, so the
// image alone would not show one). A failure names `what`.
void expect_finite_render(const ImageF& image, const FilmCounts& film, const std::string& what);

// Passes when `text` contains every one of `parts`; prints the text otherwise.
inline ::testing::AssertionResult Contains(const std::string& text, std::initializer_list<std::string> parts) {
  for (const auto& part : parts)
    if (text.find(part) == std::string::npos)
      return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
  return ::testing::AssertionSuccess();
}

}  // namespace caustica::test

#define CAUSTICA_REQUIRE_SHARED(var)                                   \
  const std::string var = ::caustica::test::shared_dir();              \
  if (var.empty()) GTEST_SKIP() << "../shared not present: skipped"
