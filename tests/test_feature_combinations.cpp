// Every feature-flag combination builds and binds (issue 38): a kernel whose
// parameter list a flag changes must be bound by the host exactly as that
// combination declares it, or a user meets "kernel X declares N arguments,
// the host binds M" instead of an image.
//
// The flags that matter are derived, not listed: for each integrator
// program, every flag of kernels/shared/feature_flags.h is turned off in
// turn from all on, and a flag that changes any kernel's parameter names is
// one that the host's binding must follow. The names come from the C
// preprocessor (fast), checked against the device's own report
// (clGetKernelArgInfo) with every flag on and every flag off.
// Then every combination of those flags renders one pass of a scene that
// holds every feature, through the session (prepare_session), which binds
// every stage it launches and checks each binding's count, names and kinds
// (KernelArgs::finish). All combinations, not pairwise: 2^k builds, k small
// (the test fails, asking for pairwise coverage, if k grows past what CI
// affords).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "host/app/session.h"
#include "host/cl/embedded_kernels.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"
#include "host/render/renderer.h"
#include "kernels/shared/feature_flags.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

using test::runtime;

constexpr const char* kIntegratorPrograms[] = {"integrator_binary.cl", "integrator_phong.cl", "integrator_path.cl"};

// kernel name -> its parameter names
using Signatures = std::map<std::string, std::vector<std::string>>;

std::string flag_options(const std::vector<int>& values) {
  std::string options;
  for (int i = 0; i < kFeatureFlagCount; ++i)
    options += std::string(" -D") + kFeatureFlags[i].name + "=" + std::to_string(values[size_t(i)]);
  return options;
}

std::string embedded_text(const std::string& path) {
  for (const EmbeddedKernelFile& f : embedded_kernel_files())
    if (f.path == path) return f.text;
  throw Error("no embedded kernel file " + path);
}

// The kernels' parameter names as the C preprocessor leaves them: the
// program file expanded as the runtime expands it, through the host's
// compiler with -E (a few milliseconds, where an OpenCL build of the path
// tracer takes seconds), then each `__kernel void name(...)`'s parameters,
// split at top-level commas, each named by its last identifier.
Signatures preprocessed_signatures(const std::string& program_file, const std::vector<int>& values) {
  const std::string source = expand_kernel_source(program_file, embedded_text(program_file));
  const std::string dir = test::temp_dir();
  const std::string in_path = dir + "/program.cl", out_path = dir + "/program.i";
  {
    std::ofstream out(in_path, std::ios::binary);
    out << source;
  }
  const std::string command = std::string(CAUSTICA_CXX_COMPILER) +
                              " -E -P -x c -D__OPENCL_C_VERSION__=120 -D__OPENCL_VERSION__=120" +
                              " -DCAUSTICA_CPU_PREFETCH" + flag_options(values) + " " + in_path + " -o " + out_path +
                              " 2>" + dir + "/cpp.log";
  if (std::system(command.c_str()) != 0) throw Error("preprocessing " + program_file + " failed: " + command);
  const std::string text = test::slurp(out_path);
  static const std::regex kernel_head(R"re(__kernel\s+void\s+([A-Za-z_][A-Za-z0-9_]*)\s*\()re");
  static const std::regex last_identifier(R"re(([A-Za-z_][A-Za-z0-9_]*)\s*$)re");
  Signatures out;
  for (std::sregex_iterator it(text.begin(), text.end(), kernel_head), end; it != end; ++it) {
    size_t pos = size_t(it->position(0) + it->length(0));
    int depth = 1;
    std::vector<std::string> params;
    std::string current;
    for (; pos < text.size() && depth > 0; ++pos) {
      const char c = text[pos];
      if (c == '(') ++depth;
      if (c == ')') --depth;
      if ((c == ',' && depth == 1) || depth == 0) {
        std::smatch m;
        if (std::regex_search(current, m, last_identifier)) params.push_back(m[1]);
        current.clear();
      } else {
        current += c;
      }
    }
    out[(*it)[1]] = params;
  }
  return out;
}

// What the device reports for the same program and flags.
Signatures device_signatures(const std::string& program_file, const std::vector<int>& values) {
  BuiltProgram built = runtime().build_file(program_file, flag_options(values));
  std::vector<cl::Kernel> kernels;
  built.program.createKernels(&kernels);
  Signatures out;
  for (const cl::Kernel& k : kernels) {
    std::string name = k.getInfo<CL_KERNEL_FUNCTION_NAME>();
    name.resize(std::min(name.size(), name.find('\0')));
    out[name] = kernel_arg_names(k);
  }
  return out;
}

// The flags whose value changes some kernel's parameter list in this
// program: each turned off from all on. (A flag whose parameters sit inside
// another flag's #if is found while that one is on; with it off they cannot
// matter.)
std::vector<int> signature_flags(const std::string& program_file) {
  const std::vector<int> all_on(size_t(kFeatureFlagCount), 1);
  const Signatures base = preprocessed_signatures(program_file, all_on);
  std::vector<int> flags;
  for (int i = 0; i < kFeatureFlagCount; ++i) {
    std::vector<int> values = all_on;
    values[size_t(i)] = 0;
    if (preprocessed_signatures(program_file, values) != base) flags.push_back(i);
  }
  return flags;
}

// The derivation reads what the device compiles: the same kernels with the
// same parameter names, with every flag on and every flag off.
TEST(FeatureCombinations, PreprocessedSignaturesAreTheDevicesOwn) {
  for (const char* file : kIntegratorPrograms)
    for (int value : {0, 1}) {
      const std::vector<int> values(size_t(kFeatureFlagCount), value);
      const Signatures device = device_signatures(file, values);
      if (device.empty() || device.begin()->second.empty()) GTEST_SKIP() << "the device reports no argument names";
      EXPECT_EQ(preprocessed_signatures(file, values), device) << file << " with every flag " << value;
    }
}

// Turning a flag that no kernel's parameters depend on does change nothing;
// the check above would not notice a derivation that found none at all.
TEST(FeatureCombinations, ThePhotonPassChangesTheShadeStagesParameters) {
  const auto has = [](const std::vector<int>& flags, FeatureFlag f) {
    return std::find(flags.begin(), flags.end(), int(f)) != flags.end();
  };
  EXPECT_TRUE(has(signature_flags("integrator_path.cl"), FeatureFlag::kHAS_CAUSTICS));
  EXPECT_TRUE(has(signature_flags("integrator_phong.cl"), FeatureFlag::kHAS_CAUSTICS));
}

// The binding check sees kinds as well as names: a value where the kernel
// takes a buffer (or the reverse) is named, position and both kinds.
TEST(FeatureCombinations, ABindingOfTheWrongKindIsNamed) {
  BuiltProgram built = runtime().build_source(
      "kinds.cl", "__kernel void takes(__global float* values, uint count) { values[0] = (float)count; }\n", "");
  cl::Buffer buffer(runtime().context(), CL_MEM_READ_WRITE, sizeof(float));
  {
    StageKernel stage(built.program, "takes");
    EXPECT_NO_THROW(KernelArgs(stage).arg("values", buffer).arg("count", cl_uint(1)).finish());
  }
  StageKernel stage(built.program, "takes");
  const std::string message =
      test::error_of([&] { KernelArgs(stage).arg("values", cl_uint(1)).arg("count", cl_uint(1)).finish(); });
  if (kernel_arg_names(stage.kernel).empty()) GTEST_SKIP() << "the device reports no argument info";
  EXPECT_TRUE(test::Contains(message, {"kernel takes", "argument 0", "\"values\"", "is a buffer", "binds a value"}))
      << message;
  StageKernel swapped(built.program, "takes");
  const std::string reverse =
      test::error_of([&] { KernelArgs(swapped).arg("values", buffer).arg("count", buffer).finish(); });
  EXPECT_TRUE(test::Contains(reverse, {"argument 1", "\"count\"", "is a value", "binds a buffer"})) << reverse;
}

// A scene with every feature in it: spheres, a cylinder, textured triangles
// with texture coordinates, a point and an area light, a mirror and glass
// (casters) over diffuse receivers, and a sky.
std::string everything_scene() {
  const std::string texture = test::source_dir() + "/textures/tiles.png";
  const std::string diffuse =
      R"({"ks": 0.1, "kd": 0.9, "specularexponent": 20, "diffusecolor": [0.8, 0.8, 0.8], "specularcolor": [1, 1, 1], "isreflective": false, "reflectivity": 0, "isrefractive": false, "refractiveindex": 1)";
  const std::string textured = diffuse + R"(, "texture": ")" + texture + R"("})";
  return R"({"nbounces": 4, "rendermode": "pathtracer",
 "camera": {"type": "pinhole", "width": 8, "height": 6, "position": [0, 1.5, 5], "lookAt": [0, 0.5, 0], "upVector": [0, 1, 0], "fov": 50, "exposure": 0},
 "scene": {"environment": {"sky": {"resolution": [16, 8]}},
  "lightsources": [{"type": "pointlight", "position": [-2, 3.5, 1], "intensity": [0.7, 0.7, 0.7]},
                   {"type": "arealight", "position": [0.5, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5], "intensity": [20, 20, 20]}],
  "shapes": [
   {"type": "triangle", "v0": [-3, 0, -2], "v1": [-3, 0, 3], "v2": [3, 0, 3], "uv0": [0, 0], "uv1": [0, 4], "uv2": [4, 4], "material": )" +
         textured + R"(},
   {"type": "triangle", "v0": [-3, 0, -2], "v1": [3, 0, 3], "v2": [3, 0, -2], "uv0": [0, 0], "uv1": [4, 4], "uv2": [4, 0], "material": )" +
         textured + R"(},
   {"type": "sphere", "center": [-0.8, 0.5, 0], "radius": 0.5, "material": {"ks": 0, "kd": 0, "specularexponent": 1, "diffusecolor": [1, 1, 1], "specularcolor": [1, 1, 1], "isreflective": false, "reflectivity": 0, "isrefractive": true, "refractiveindex": 1.5}},
   {"type": "sphere", "center": [0.8, 0.5, 0], "radius": 0.5, "material": {"ks": 0, "kd": 0, "specularexponent": 1, "diffusecolor": [1, 1, 1], "specularcolor": [1, 1, 1], "isreflective": true, "reflectivity": 1, "isrefractive": false, "refractiveindex": 1}},
   {"type": "cylinder", "center": [0, 0.4, -1], "axis": [0, 1, 0], "radius": 0.2, "height": 0.4, "material": )" +
         diffuse + R"(}}
  ]}})";
}

bool& flag_field(SceneFeatures& f, FeatureFlag flag) {
  switch (flag) {
    case FeatureFlag::kHAS_CAUSTICS: return f.caustics;
    case FeatureFlag::kHAS_NUMERIC_CHECKS: return f.check_numerics;
    case FeatureFlag::kHAS_AUX_PASSES: return f.aux_passes;
    case FeatureFlag::kHAS_ENVIRONMENT: return f.environment;
    case FeatureFlag::kHAS_TEXTURES: return f.textures;
    case FeatureFlag::kHAS_LIGHTS: return f.lights;
    case FeatureFlag::kHAS_AREA_LIGHTS: return f.area_lights;
    case FeatureFlag::kHAS_REFLECTION: return f.reflection;
    case FeatureFlag::kHAS_REFRACTION: return f.refraction;
    case FeatureFlag::kHAS_SPHERES: return f.spheres;
    case FeatureFlag::kHAS_CYLINDERS: return f.cylinders;
    case FeatureFlag::kHAS_TRIANGLES: return f.triangles;
    case FeatureFlag::kHAS_TRIANGLE_SHADING: return f.triangle_shading;
    default: break;
  }
  throw Error(std::string("the test cannot set ") + kFeatureFlags[int(flag)].name +
              " on SceneFeatures: add it to flag_field");
}

// Every combination of the flags that change a kernel's parameters, in each
// mode, renders a pass: every stage the render launches binds (and
// KernelArgs::finish checks count, names and kinds on its first binding).
TEST(FeatureCombinations, EveryCombinationBuildsAndBinds) {
  const std::string path = test::write_scene("everything.json", everything_scene());
  const std::pair<RenderMode, const char*> modes[] = {
      {RenderMode::Binary, "integrator_binary.cl"}, {RenderMode::Phong, "integrator_phong.cl"},
      {RenderMode::Path, "integrator_path.cl"}};
  for (const auto& [mode, file] : modes) {
    const std::vector<int> flags = signature_flags(file);
    // 2^k builds of a few seconds each on 2 cores: past 5 flags, cover
    // pairs instead (each pair of flags in all four value pairs).
    ASSERT_LE(flags.size(), 5u) << file << ": too many flags change parameters for all combinations";
    for (uint32_t combination = 0; combination < (1u << flags.size()); ++combination) {
      std::string what = std::string(file) + " with";
      SessionOptions o;
      o.scene_path = path;
      o.mode = mode;
      o.device = test::device_spec();
      o.spp = 1;
      o.adaptive = false;
      o.error_estimate = false;
      o.caustics = CausticsMode::On;
      o.edit_features = [&](SceneFeatures& f) {
        for (size_t b = 0; b < flags.size(); ++b) {
          const bool on = (combination >> b) & 1u;
          flag_field(f, FeatureFlag(flags[b])) = on;
          what += std::string(" ") + kFeatureFlags[flags[b]].name + "=" + (on ? "1" : "0");
        }
      };
      try {
        auto session = prepare_session(o);
        RenderStats stats;
        const ImageF image = session->renderer->render(&stats);
        EXPECT_EQ(image.width, 8) << what;
        EXPECT_GT(stats.launches, 0u) << what;
        if (session->features.caustics && mode == RenderMode::Path)
          EXPECT_GT(stats.photon_maps, 0u) << what << ": the photon stages never ran";
      } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": " << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace caustica
