// Bad input through the command line, as a new user would give it (issue 14,
// point 2): a table of arguments and small generated input files, each run
// through the built binary. Rules every row holds to: the process exits on
// its own (no signal), never prints "terminate called", sanitizer output or
// std::bad_alloc; a rejected input exits non-zero with one line naming the
// option, file, JSON key or line and what was expected, and nothing was
// "wrote". Rows that are only warnings (an unreadable texture becomes a
// checker) exit 0 with the warning. A crash the fuzz targets (fuzz/) find
// becomes a row here or a unit test next to its parser.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/app/cli.h"
#include "host/error.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
Result run_caustica(const std::string& args) {
  Result r = test::run_cli(args);
  // Oclgrind's compiler prints clang's "N warnings generated." to the
  // process's stderr on a cold build (no program cache yet), before any
  // message of caustica's: not caustica's output, so not judged as a line.
  if (test::on_simulator()) {
    std::string kept;
    for (size_t start = 0; start < r.output.size();) {
      const size_t end = std::min(r.output.find('\n', start), r.output.size() - 1) + 1;
      const std::string line = r.output.substr(start, end - start);
      const size_t digits = line.find_first_not_of("0123456789");
      const bool summary = digits > 0 && digits != std::string::npos &&
                           (line.compare(digits, std::string::npos, " warning generated.\n") == 0 ||
                            line.compare(digits, std::string::npos, " warnings generated.\n") == 0);
      if (!summary) kept += line;
      start = end;
    }
    r.output = kept;
  }
  return r;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = test::temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

// A valid 24x16 phong scene; `shapes` and `lights` are JSON array texts.
std::string scene(const std::string& shapes, const std::string& lights = "", int nbounces = 2) {
  return R"({"nbounces": )" + std::to_string(nbounces) + R"(, "rendermode": "phong",
    "camera": {"type": "pinhole", "width": 24, "height": 16, "position": [0, 0, -3], "lookAt": [0, 0, 0],
               "upVector": [0, 1, 0], "fov": 45},
    "scene": {"backgroundcolor": [0.1, 0.1, 0.1],
              "lightsources": [)" +
         (lights.empty() ? R"({"type": "pointlight", "position": [0, 2, -2], "intensity": [1, 1, 1]})" : lights) +
         R"(], "shapes": )" + shapes + "}}";
}

const char* kSphere = R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1}])";

std::string mesh_shape(const std::string& file) { return R"([{"type": "mesh", "file": ")" + file + R"("}])"; }

std::string textured_sphere(const std::string& file) {
  return R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"texture": ")" + file + R"("}}])";
}

struct Row {
  const char* name;
  std::string args;            // after "caustica"
  bool rejected = true;        // false: a warning only, exit 0
  std::vector<std::string> expected;  // parts of the output
  bool one_line = true;        // CLI11's own parse errors add a "Run with --help" line
};

// Writes every input the rows use into the test's temporary directory.
std::vector<Row> make_rows() {
  const std::string d = test::temp_dir();
  const std::string dev = " --device " + quote(test::device_spec()) + " -q";
  const std::string ok = write_file("ok.json", scene(kSphere));

  // JSON nested 10^5 levels, at the top and where an error message shows the value.
  write_file("deep.json", std::string(100000, '[') + std::string(100000, ']'));
  write_file("deep_value.json", R"({"nbounces": )" + std::string(100000, '[') + std::string(100000, ']') + "}");
  write_file("bounces.json", scene(kSphere, "", 1000000000));

  std::string lights;
  for (int i = 0; i < 100000; ++i)
    lights += std::string(i ? "," : "") + R"({"type": "arealight", "position": [)" + std::to_string(i % 100) +
              R"(, 2, 0], "intensity": [0.001, 0.001, 0.001], "size": [0.1, 0.1]})";
  write_file("lights.json", scene(kSphere, lights));

  write_file("tiny.ppm", "P6\n16384 16384\n255\nx");  // 20 bytes declaring 16384 x 16384
  write_file("short.ppm", "P6\n1000 1000\n255\nxyz");
  write_file("tiny_texture.json", scene(textured_sphere("tiny.ppm")));
  write_file("short_texture.json", scene(textured_sphere("short.ppm")));

  const std::string tri = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n";
  write_file("kd_nan.obj", "mtllib kd_nan.mtl\n" + tri + "usemtl red\nf 1 2 3\n");
  write_file("kd_nan.mtl", "newmtl red\nKd nan 0 0\n");
  write_file("kd_negative.obj", "mtllib kd_negative.mtl\n" + tri + "usemtl red\nf 1 2 3\n");
  write_file("kd_negative.mtl", "newmtl red\nKd -1 0 0\n");
  write_file("kd_huge.obj", "mtllib kd_huge.mtl\n" + tri + "usemtl red\nf 1 2 3\n");
  write_file("kd_huge.mtl", "newmtl red\nKd 1e29 0.5 0.5\n");
  write_file("nan_vertex.obj", tri + "v nan 1 0\nf 1 2 4\n");
  write_file("inf_vertex.obj", tri + "v 0 inf 0\nf 1 2 4\n");
  write_file("huge_index.obj", tri + "f 1 2 100000000000000000000\n");
  write_file("nan_vertex.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n");
  for (const char* m : {"kd_nan.obj", "kd_negative.obj", "kd_huge.obj", "nan_vertex.obj", "inf_vertex.obj",
                        "huge_index.obj", "nan_vertex.ply"})
    write_file(fs::path(m).stem().string() + "_" + fs::path(m).extension().string().substr(1) + ".json",
               scene(mesh_shape(m)));

  // glTF: a truncated .glb, a node cycle placed as a coursework mesh, and
  // --camera where it does not apply.
  write_file("truncated.glb", std::string("glTF\x02\0\0\0\xff\xff\0\0", 12));
  write_file("cycle.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
    "nodes": [{"children": [1]}, {"children": [0]}]})");
  write_file("cycle_gltf.json", scene(mesh_shape("cycle.gltf")));

  // Writes that fail: /dev/full takes the open and refuses every byte.
  for (const char* ext : {"png", "exr", "ppm", "pfm"}) {
    std::error_code ec;
    fs::create_symlink("/dev/full", d + "/full." + ext, ec);
  }

  // Issue 24's two black images: one value of 1e29 had left the film a
  // resolution of 2^41, so every ordinary value rounded to 0, exit 0.
  write_file("huge_diffuse.json",
             scene(R"([{"type": "triangle", "v0": [-1, -1, 0], "v1": [1, -1, 0], "v2": [0, 1, 0],
                         "material": {"diffusecolor": [1.2e29, 0.5, 0.5]}}])"));
  write_file("huge_ks.json", scene(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                        "material": {"ks": 1e29}}])"));

  // A directional light without a direction to travel, or without its irradiance.
  write_file("directional_zero.json",
             scene(kSphere, R"({"type": "directional", "direction": [0, 0, 0], "intensity": [1, 1, 1]})"));
  write_file("directional_no_intensity.json", scene(kSphere, R"({"type": "directional", "direction": [0, -1, 0]})"));

  const std::string missing = quote(d + "/no_such_scene.json");
  std::vector<Row> rows = {
      {"reflectance_1e29", "render " + quote(d + "/huge_diffuse.json"), true,
       {"huge_diffuse.json: /scene/shapes/0/material/diffusecolor/0: expected a reflectance in [0, 100]",
        "1.2e+29"}},
      {"phong_ks_1e29", "render " + quote(d + "/huge_ks.json"), true,
       {"huge_ks.json: /scene/shapes/0/material/ks: expected a reflectance in [0, 100]", "1e+29"}},
      {"deep_json", "render " + quote(d + "/deep.json"), true, {"deep.json: /0/0/0", "nested at most 64 levels"}},
      {"deep_json_value", "render " + quote(d + "/deep_value.json"), true, {"deep_value.json: /nbounces/0", "64 levels"}},
      {"bvh_render", "render " + quote(ok) + " --bvh foo", true, {"--bvh foo: expected fast, sah or spatial"}},
      {"bvh_bench", "bench " + quote(ok) + " --bvh foo", true, {"--bvh foo: expected fast, sah or spatial"}},
      {"scene_dev_zero", "render /dev/zero", true, {"/dev/zero: is a character device, expected a regular file"}},
      {"scene_dev_urandom", "render /dev/urandom", true, {"/dev/urandom: is a character device"}},
      {"scene_directory", "render " + quote(d), true, {"is a directory, expected a regular file"}},
      {"scene_missing", "render " + missing, true, {"no_such_scene.json: scene file not found"}},
      {"texture_20_bytes_16384", "render " + quote(d + "/tiny_texture.json") + " -o " + quote(d + "/t.png") + dev,
       false, {"tiny.ppm", "16384 x 16384", "texture limit of 16384 per side"}},
      {"texture_truncated", "render " + quote(d + "/short_texture.json") + " -o " + quote(d + "/s.png") + dev,
       false, {"short.ppm", "1000 x 1000", "pixels in a file of 20 bytes"}},
      {"image_too_large", "render " + quote(ok) + " --width 100000 --height 10000", true,
       {"--width/--height 100000x10000", "image limit of 32768 pixels per side"}},
      {"image_too_large_area", "render " + quote(ok) + " --width 30000 --height 30000", true,
       {"268435456 pixels"}},
      {"bounces", "render " + quote(d + "/bounces.json"), true,
       {"bounces.json: /nbounces: expected an integer in [0, 1024], got 1000000000"}},
      {"lights_100000_phong", "render " + quote(d + "/lights.json") + dev, true,
       {"lights.json: /scene/lightsources", "100000 lights", "limit is 1024"}},
      {"directional_zero_direction", "render " + quote(d + "/directional_zero.json") + dev, true,
       {"directional_zero.json: /scene/lightsources/0/direction: expected a direction of nonzero length", "[0,0,0]"}},
      {"directional_no_intensity", "render " + quote(d + "/directional_no_intensity.json") + dev, true,
       {"directional_no_intensity.json: /scene/lightsources/0/intensity: required key \"intensity\" is missing"}},
      {"exposure_empty", "render " + quote(ok) + " --exposure ''", true, {"--exposure '': expected", "[-64, 64]"}},
      {"exposure_nan", "render " + quote(ok) + " --exposure nan", true, {"--exposure 'nan': expected"}},
      {"exposure_huge", "render " + quote(ok) + " --exposure 1e9", true, {"--exposure '1e9': expected"}},
      {"gamma_zero", "render " + quote(ok) + " --gamma 0", true, {"--gamma '0': expected"}},
      // Checked before the scene is read: the scene does not even exist.
      {"output_extension", "render " + missing + " -o out.bmp", true, {"out.bmp", "unknown extension '.bmp'"}},
      {"output_directory", "render " + missing + " -o " + quote(d + "/no/dir/x.png"), true,
       {"x.png", "does not exist"}},
      {"tonemap", "render " + missing + " --tonemap foo", true, {"--tonemap", "'foo'", "linear, reinhard, aces"}},
      {"plot_extension", "render " + missing + " --report r.csv --plot p.jpg", true, {"--plot p.jpg", ".png or .svg"}},
      {"checkpoint_every_alone", "render " + missing + " --checkpoint-every 5", true,
       {"--checkpoint-every needs --checkpoint"}},
      {"checkpoint_directory", "render " + missing + " --checkpoint " + quote(d + "/no/dir/s.cst"), true,
       {"--checkpoint", "s.cst", "does not exist"}},
      {"resume_missing", "render " + missing + " --resume " + quote(d + "/none.cst"), true,
       {"none.cst: state file not found"}},
      {"resume_not_a_state", "render " + missing + " --resume " + quote(ok), true,
       {"ok.json: not a caustica state file"}},
      {"resume_dev_zero", "render " + missing + " --resume /dev/zero", true, {"/dev/zero: is a character device"}},
      {"width_not_a_number", "render " + quote(ok) + " --width abc", true, {"--width", "abc"}, false},
      {"kd_nan", "render " + quote(d + "/kd_nan_obj.json"), true,
       {"/scene/shapes/0/file", "kd_nan.mtl: line 2: Kd: expected 1 or 3 finite non-negative numbers, got 'nan 0 0'"}},
      {"kd_negative", "render " + quote(d + "/kd_negative_obj.json"), true, {"kd_negative.mtl: line 2: Kd", "'-1 0 0'"}},
      {"kd_huge", "render " + quote(d + "/kd_huge_obj.json"), true,
       {"kd_huge.mtl: line 2: Kd: expected a reflectance in [0, 100]", "'1e29 0.5 0.5'"}},
      {"obj_nan_vertex", "render " + quote(d + "/nan_vertex_obj.json"), true,
       {"nan_vertex.obj: line 4: expected a finite vertex coordinate", "'nan'"}},
      {"obj_inf_vertex", "render " + quote(d + "/inf_vertex_obj.json"), true, {"inf_vertex.obj: line 4", "'inf'"}},
      {"obj_huge_index", "render " + quote(d + "/huge_index_obj.json"), true,
       {"huge_index.obj: line 4: expected face indices", "'100000000000000000000'"}},
      {"gltf_truncated_glb", "render " + quote(d + "/truncated.glb"), true, {"truncated.glb: ", "glTF"}},
      {"gltf_cycle_as_mesh", "render " + quote(d + "/cycle_gltf.json"), true,
       {"/scene/shapes/0/file", "cycle.gltf: /nodes/1/children/0: node 0 is its own ancestor"}},
      {"gltf_camera_on_json", "render " + quote(ok) + " --camera 1", true, {"--camera 1: ", "ok.json is not a glTF file"}},
      {"gltf_camera_missing", "render " + quote(test::source_dir() + "/scenes/gltf_example.gltf") + " --camera 3", true,
       {"--camera 3: ", "gltf_example.gltf has 1 camera (0 to 0)"}},
      {"ply_nan_vertex", "render " + quote(d + "/nan_vertex_ply.json"), true,
       {"nan_vertex.ply: PLY element 'vertex' item 3 of 3 (line 12): expected a finite 'x'"}},
  };
  for (const char* ext : {"png", "exr", "ppm", "pfm"})
    rows.push_back({"full_disk", "render " + quote(ok) + " -o " + quote(d + "/full." + std::string(ext)) + dev, true,
                    {"full." + std::string(ext), "No space left on device"}});
  return rows;
}

TEST(CliErrors, EveryBadInputIsOneClearLineNeverACrash) {
  for (const Row& row : make_rows()) {
    SCOPED_TRACE(std::string(row.name) + ": caustica " + row.args);
    const Result r = run_caustica(row.args);
    EXPECT_FALSE(r.signalled) << r.output;
    for (const char* never : {"terminate called", "Sanitizer", "runtime error:", "std::bad_alloc", "Segmentation"})
      EXPECT_EQ(r.output.find(never), std::string::npos) << never << " in: " << r.output;
    for (const auto& part : row.expected) EXPECT_TRUE(test::Contains(r.output, {part}));
    if (row.rejected) {
      EXPECT_NE(r.status, 0) << r.output;
      EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
      if (row.one_line) {
        EXPECT_EQ(r.output.rfind("caustica: error: ", 0), 0u) << r.output;
        EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "more than one line: " << r.output;
      }
    } else {
      EXPECT_EQ(r.status, 0) << r.output;
    }
  }
}

// Every floating-point option, table-driven, with values CLI11's own
// validators let through (NaN, infinities) and those out of its range: each
// is refused before any work, with the option's name and what it expects
// (issue 38: `sky --sun-elevation nan` crashed, `--checkpoint-every nan`
// and `--caustic-radius nan` were accepted).
TEST(CliErrors, EveryFloatingOptionRefusesNanInfinityAndOutOfRange) {
  const std::string d = test::temp_dir();
  const std::string ok = quote(write_file("ok.json", scene(kSphere)));
  const std::string dev = " --device " + quote(test::device_spec()) + " -q";
  struct Option {
    std::string command;  // everything but the value
    std::vector<std::string> refused;
  };
  const std::vector<Option> options = {
      {"render " + ok + " --mode path --spp 1" + dev + " -o " + quote(d + "/x.png") + " --time", {"0", "-1", "1e38"}},
      {"render " + ok + " --mode path --spp 1" + dev + " -o " + quote(d + "/x.png") + " --write-every",
       {"0", "-1", "1e38"}},
      {"render " + ok + " --mode path --spp 1" + dev + " -o " + quote(d + "/x.png") + " --target-error", {"0", "-1"}},
      {"render " + ok + " --mode path --spp 1" + dev + " -o " + quote(d + "/x.png") + " --caustics on --caustic-radius",
       {"0", "-1", "1e38"}},
      {"render " + ok + " --mode path --spp 1" + dev + " -o " + quote(d + "/x.png") + " --checkpoint " +
           quote(d + "/s.cst") + " --checkpoint-every",
       {"0", "-1", "1e38"}},
      {"render " + ok + dev + " -o " + quote(d + "/x.png") + " --exposure", {"1e38", "-1e38"}},
      {"render " + ok + dev + " -o " + quote(d + "/x.png") + " --gamma", {"0", "-1", "1e38"}},
      {"sky -o " + quote(d + "/sky.pfm") + " --width 16 --height 8 --sun-elevation", {"0", "-1", "1e38", "1e-38"}},
      {"sky -o " + quote(d + "/sky.pfm") + " --width 16 --height 8 --sun-azimuth", {"1e38", "-1e38"}},
      {"sky -o " + quote(d + "/sky.pfm") + " --width 16 --height 8 --turbidity", {"0", "-1", "1e38", "1e-38"}},
      {"merge " + quote(d + "/none.cst") + " -o " + quote(d + "/m.pfm") + " --exposure", {"1e38", "-1e38"}},
  };
  for (const Option& o : options) {
    std::vector<std::string> values{"nan", "NaN", "inf", "-inf", "infinity"};
    values.insert(values.end(), o.refused.begin(), o.refused.end());
    const std::string name = o.command.substr(o.command.rfind(' ') + 1);
    for (const std::string& v : values) {
      SCOPED_TRACE("caustica " + o.command + " " + v);
      const Result r = run_caustica(o.command + " " + v);
      EXPECT_FALSE(r.signalled) << r.output;
      EXPECT_NE(r.status, 0) << r.output;
      EXPECT_TRUE(test::Contains(r.output, {name})) << r.output;
      EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
    }
  }
}

// Every numeric option of every command, found by walking the command
// line's own definition (make_cli), not listed: each takes NaN, +-inf, 0,
// -1, 1e-38 and 1e38 and is parsed and checked in process as `main` does
// before any work. A value is refused with a message naming the option, or
// accepted; an accepted one then runs, as a process, on a small scene, and
// must finish on its own (the timeout of run_cli) with its output written
// or a message naming the option: never a crash, a hang or a silent NaN.
TEST(CliErrors, EveryNumericOptionOfEveryCommandIsCheckedByName) {
  const std::string d = test::temp_dir();
  const std::string ok = write_file("ok.json", scene(kSphere));
  // The least each command needs besides the option under test.
  const std::map<std::string, std::vector<std::string>> base = {
      {"render", {ok, "-o", d + "/x.pfm", "-q", "--device", test::device_spec()}},
      {"bench", {ok, "--device", test::device_spec()}},
      {"sky", {"-o", d + "/sky.pfm"}},
      {"generate", {"-o", d + "/g.json"}},
      {"merge", {d + "/none.cst", "-o", d + "/m.pfm"}},
      {"denoise", {d + "/none.pfm", "-o", d + "/dn.pfm"}},
      {"diff", {d + "/none.pfm", d + "/none2.pfm"}},
      {"plot", {d + "/none.csv", "-o", d + "/p.png"}},
      {"devices", {}}};
  const std::vector<std::string> values = {"nan", "inf", "-inf", "0", "-1", "1e-38", "1e38"};
  const std::unique_ptr<Cli> walk = make_cli();
  size_t options = 0, refused = 0;
  std::vector<std::string> accepted;
  for (const CLI::App* command : walk->app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string name = command->get_name();
    ASSERT_TRUE(base.count(name)) << "a command this test does not know: " << name;
    for (const CLI::Option* option : command->get_options()) {
      const std::string type = option->get_type_name();
      if (option->get_positional() || option->get_expected_max() == 0) continue;  // flags
      if (type.find("FLOAT") == std::string::npos && type.find("INT") == std::string::npos &&
          type.find("NUMBER") == std::string::npos)
        continue;
      ++options;
      const std::string flag = option->get_name(false, false).substr(0, option->get_name(false, false).find(','));
      for (const std::string& value : values) {
        std::vector<std::string> words = {"caustica", name};
        words.insert(words.end(), base.at(name).begin(), base.at(name).end());
        words.insert(words.end(), {flag, value});
        // Options that need a partner to be checked at all.
        if (flag == "--checkpoint-every") words.insert(words.end(), {"--checkpoint", d + "/s.cst"});
        if (flag == "--caustic-radius" || flag == "--photons") words.insert(words.end(), {"--caustics", "on"});
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        const std::unique_ptr<Cli> cli = make_cli();
        std::string message;
        try {
          cli->app.parse(int(argv.size()), argv.data());
          check_command_options(*cli);
        } catch (const CLI::Error& e) {
          message = e.what();
          if (message.empty()) message = e.get_name();
        } catch (const Error& e) {
          message = e.what();
        }
        if (message.empty()) {
          std::string line;
          for (size_t i = 1; i < words.size(); ++i) line += (i > 1 ? " " : "") + quote(words[i]);
          accepted.push_back(line);
          continue;
        }
        ++refused;
        const std::string bare = flag.substr(flag.find_first_not_of('-'));
        EXPECT_NE(message.find(bare), std::string::npos)
            << name << " " << flag << " " << value << ": the message does not name the option: " << message;
      }
    }
  }
  EXPECT_GE(options, 25u);
  // The accepted ones run, on a 24x16 phong scene or a 16x8 sky (their
  // inputs for merge, denoise, diff and plot do not exist: those commands
  // stop at the file, naming it).
  size_t ran = 0;
  for (const std::string& line : accepted) {
    if (line.rfind("'render'", 0) != 0 && line.rfind("'sky'", 0) != 0 && line.rfind("'generate'", 0) != 0) continue;
    SCOPED_TRACE(line);
    const Result r = run_caustica(line);
    ++ran;
    EXPECT_FALSE(r.signalled) << r.output;
    EXPECT_NE(r.status, 124) << "did not finish: " << r.output;
    EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("nan"), std::string::npos) << r.output;
  }
  std::printf("[measure] %zu numeric options, %zu values refused by name, %zu accepted (%zu of them run)\n", options,
              refused, accepted.size(), ran);
}

}  // namespace
}  // namespace caustica
