// OpenCL plumbing: device selection by index / type / name, clear errors for
// devices that do not exist and kernels that do not build (with the build log
// pointing at the original file and line), the program cache, and the CLI's
// error reporting end to end.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <sys/wait.h>

#include "host/cl/embedded_kernels.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::error_of;

TEST(DeviceSelection, ByTypeIndexAndName) {
  const auto devices = list_devices();
  ASSERT_FALSE(devices.empty());
  // Every type present is found by its name (the test device may be a GPU
  // alone, or PoCL's CPU alone).
  for (const auto& d : devices)
    if (d.platform_name.find("Oclgrind") == std::string::npos) EXPECT_EQ(select_device(d.type).type, d.type);
  EXPECT_EQ(select_device("0").index, 0);
  EXPECT_EQ(select_device(devices.back().name.substr(0, 6)).name.substr(0, 6), devices.back().name.substr(0, 6));
  for (const auto& d : devices) {
    EXPECT_GT(d.compute_units, 0u);
    EXPECT_FALSE(d.device_version.empty());
  }
}

TEST(DeviceSelection, UnknownDeviceListsTheAvailableOnes) {
  const std::string msg = error_of([] { select_device("no-such-device-xyz"); });
  EXPECT_NE(msg.find("no-such-device-xyz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("available devices"), std::string::npos) << msg;
  EXPECT_NE(error_of([] { select_device("999"); }).find("no device with that index"), std::string::npos);
}

TEST(ProgramBuild, FailureCarriesTheLogAtTheOriginalLine) {
  // tests/kernels/runtime_broken.cl: an include, then an undefined name on line 9.
  const std::string msg = error_of([&] { test::build_test_kernel("runtime_broken.cl", ""); });
  EXPECT_NE(msg.find("kernel build failed for tests/kernels/runtime_broken.cl"), std::string::npos) << msg;
  EXPECT_NE(msg.find("undefined_name"), std::string::npos) << msg;
  // PoCL honours the #line markers; Oclgrind ("input.cl:312") and NVIDIA
  // ("<kernel>:330:10") count physical lines, which the runtime maps back.
  EXPECT_NE(msg.find("tests/kernels/runtime_broken.cl:9"), std::string::npos)
      << "log should point at line 9 of tests/kernels/runtime_broken.cl:\n" << msg;
}

TEST(ProgramBuild, MissingTestKernelIsNamed) {
  const std::string msg = error_of([&] { test::build_test_kernel("no_such_kernel.cl", ""); });
  EXPECT_NE(msg.find("tests/kernels/no_such_kernel.cl"), std::string::npos) << msg;
}

TEST(ProgramBuild, PhysicalLinesInALogAreMappedToTheirFiles) {
  const std::string source = expand_kernel_source("broken.cl", "#include \"shared/types.h\"\nint a;\nx = 1;\n");
  // Physical line of "x = 1;" in the expanded source.
  std::istringstream in(source);
  int physical = 0, target = 0;
  for (std::string line; std::getline(in, line);)
    if (++physical && line == "x = 1;") target = physical;
  ASSERT_GT(target, 3);
  const std::string log = "<kernel>:" + std::to_string(target) + ":3: error: x\ninput.cl:" + std::to_string(target) +
                          ": error: y\nbroken.cl:3:1: error: z\n<kernel>:99999:1: note: past the end\n";
  EXPECT_EQ(map_build_log_lines(log, source),
            "broken.cl:3:3: error: x\nbroken.cl:3: error: y\nbroken.cl:3:1: error: z\n<kernel>:99999:1: note: past the end\n");
  // Lines 1 and 2 are the markers naming the root file and its include.
  EXPECT_EQ(map_build_log_lines("<source>:3:1: w", source), "shared/types.h:1:1: w");
}

TEST(ProgramBuild, MissingIncludeIsNamed) {
  const std::string msg =
      error_of([&] { test::runtime().build_source("inc.cl", "#include \"lib/nope.h\"\n", ""); });
  EXPECT_NE(msg.find("inc.cl:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("lib/nope.h"), std::string::npos) << msg;
}

// The include expander honours #if (issue 21): a file first included
// inside a false #if is compiled where it is next included; one included
// inside a true #if is not compiled twice; #line markers still name the
// original lines.
TEST(ProgramBuild, IncludesInsideIfAreDecidedByThePreprocessor) {
  const std::string expanded =
      expand_kernel_source("runtime_if_include.cl", test::test_kernel_source("runtime_if_include.cl"));
  EXPECT_NE(expanded.find("#ifndef CS_INCLUDED_lib_2Foptics_2Eh"), std::string::npos) << expanded;
  for (const char* condition : {"0", "1", "HAS_CAUSTICS"}) {
    const BuiltProgram built = test::build_test_kernel("runtime_if_include.cl", std::string("-DCONDITION=") + condition);
    cl::Kernel k(built.program, "k");
    cl::Buffer out(test::runtime().context(), CL_MEM_WRITE_ONLY, sizeof(float));
    k.setArg(0, out);
    test::runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NullRange);
    float r = 0.0f;
    test::runtime().queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof r, &r);
    EXPECT_NEAR(r, 0.04f, 1e-6f) << "#if " << condition;  // ((1 - 1.5) / (1 + 1.5))^2
  }
  // The C++ side of a shared header is known dead: its includes are dropped
  // (they need not be kernel files), and the OpenCL side counts as
  // unconditional.
  EXPECT_NO_THROW(test::build_test_kernel("runtime_shared_header.cl", ""));
  // The integrators' programs inline every file once (no copies of headers
  // that shared headers include for OpenCL only).
  for (const char* program : {"integrator_binary.cl", "integrator_phong.cl", "integrator_path.cl"}) {
    std::string text;
    for (const auto& f : embedded_kernel_files())
      if (f.path == program) text = f.text;
    const std::string expanded = expand_kernel_source(program, text);
    std::istringstream in(expanded);
    std::set<std::string> guards;
    std::string repeated;
    int copies = 0;
    for (std::string line; std::getline(in, line);)
      if (line.rfind("#ifndef CS_INCLUDED_", 0) == 0) {
        ++copies;
        if (!guards.insert(line).second) repeated += " " + line.substr(20);
      }
    EXPECT_GT(copies, 10) << program;
    EXPECT_EQ(copies, int(guards.size())) << program << ": a file inlined more than once:" << repeated;
  }
  // The build log still points at the root file's own line.
  const std::string msg = error_of([&] { test::build_test_kernel("runtime_broken_if.cl", ""); });
  EXPECT_NE(msg.find("tests/kernels/runtime_broken_if.cl:11"), std::string::npos) << msg;
  const std::string source =
      expand_kernel_source("tests/kernels/runtime_broken_if.cl", test::test_kernel_source("runtime_broken_if.cl"));
  std::istringstream in(source);
  int physical = 0, target = 0;
  for (std::string line; std::getline(in, line);)
    if (++physical && line == "  x[0] = undefined_name;") target = physical;
  EXPECT_EQ(map_build_log_lines("<kernel>:" + std::to_string(target) + ":3: e", source),
            "tests/kernels/runtime_broken_if.cl:11:3: e");
}

// Options that name the same feature flags in another order or spelling
// share one cache entry (complete_feature_flags normalises them).
// Three builds of one test kernel in a fresh cache directory: the first
// with options a, then b, then c; the first kernel of b's program is run
// on one int.
struct CacheRun {
  BuiltProgram a, b, c;
  int b_result = 0;
};
CacheRun build_in_fresh_cache(const std::string& cache, const std::string& file, const std::string& a,
                              const std::string& b, const std::string& c) {
  const std::string dir = test::temp_dir() + "/" + cache;
  setenv("CAUSTICA_CACHE_DIR", dir.c_str(), 1);
  Runtime rt(select_device(test::device_spec()));
  CacheRun run;
  run.a = test::build_test_kernel(file, a, rt);
  run.b = test::build_test_kernel(file, b, rt);
  run.c = test::build_test_kernel(file, c, rt);
  unsetenv("CAUSTICA_CACHE_DIR");
  cl::Kernel k(run.b.program, "k");
  cl::Buffer buf(rt.context(), CL_MEM_READ_WRITE, sizeof(int));
  k.setArg(0, buf);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NullRange);
  rt.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof run.b_result, &run.b_result);
  return run;
}

TEST(ProgramBuild, SameFlagsInAnotherOrderShareTheCacheEntry) {
  const CacheRun run = build_in_fresh_cache("cache_flags", "runtime_flags.cl", "-DHAS_SPHERES -DHAS_TRIANGLES",
                                            "-DHAS_TRIANGLES=1 -DHAS_DIELECTRIC=1 -D HAS_SPHERES=1", "-DHAS_TRIANGLES");
  EXPECT_FALSE(run.a.from_cache);
  EXPECT_TRUE(run.b.from_cache) << "the same flags must give the same cache key";
  EXPECT_FALSE(run.c.from_cache);
  EXPECT_EQ(run.b_result, 7) << "every flag has a value, the unnamed ones their defaults";
}

TEST(ProgramBuild, SecondBuildComesFromTheCache) {
  const CacheRun run = build_in_fresh_cache("cache", "runtime_cached.cl", "-DVARIANT=1", "-DVARIANT=1", "-DVARIANT=2");
  EXPECT_FALSE(run.a.from_cache);
  EXPECT_TRUE(run.b.from_cache);
  EXPECT_FALSE(run.c.from_cache) << "different options must not share a cache entry";
  EXPECT_EQ(run.b_result, 7) << "the cached program must actually work";
}

using CommandResult = test::CliResult;
CommandResult run(const std::string& args) { return test::run_cli(args); }

TEST(CommandLine, BadInputsGiveClearErrorsAndExitCode1) {
  const std::string dir = test::temp_dir();
  {
    std::ofstream(dir + "/bad.json") << R"({"camera": {"width": 10}})";
  }
  auto r = run("render " + dir + "/missing.json -o " + dir + "/x.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  r = run("render " + dir + "/bad.json -o " + dir + "/x.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
  r = run("render " + test::source_dir() + "/scenes/scene.json --device no-such-device -o " + dir + "/x.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("no-such-device"), std::string::npos) << r.output;
  r = run("render " + test::source_dir() + "/scenes/scene.json --mode sketch -o " + dir + "/x.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("binary, phong or path"), std::string::npos) << r.output;
  r = run("render " + test::source_dir() + "/scenes/scene.json --tonemap filmic -o " + dir + "/x.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("reinhard"), std::string::npos) << r.output;
  r = run("render " + test::source_dir() + "/scenes/scene.json -q -o " + dir + "/x.tiff --width 8");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find(".exr"), std::string::npos) << r.output;
}

TEST(CommandLine, RendersEveryOutputFormatAndKeepsTheAspect) {
  const std::string dir = test::temp_dir();
  for (const char* ext : {"ppm", "png", "pfm", "exr"}) {
    const auto r = run("render " + test::source_dir() + "/scenes/simple_phong.json -q --width 120 -o " + dir +
                       "/out." + ext);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_GT(std::filesystem::file_size(dir + "/out." + ext), 100u) << ext;
  }
  std::ifstream ppm(dir + "/out.ppm");
  std::string magic;
  int w = 0, h = 0;
  ppm >> magic >> w >> h;
  EXPECT_EQ(magic, "P3");
  EXPECT_EQ(w, 120);
  EXPECT_EQ(h, 80);  // 1200x800 camera: aspect kept
  const auto devices = run("devices");
  EXPECT_EQ(devices.status, 0);
  EXPECT_NE(devices.output.find("[0]"), std::string::npos) << devices.output;
}

}  // namespace
}  // namespace caustica
