// The command line: every subcommand's options (CLI11), bound to their
// argument structs, and the dispatch to the command that runs. main()
// parses with it under mpirun's set-up and its error handling; the fuzz
// target fuzz/fuzz_cli.cpp parses arbitrary argument lists with it and
// runs the checks each command makes before it reads or renders anything.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "host/app/bench.h"
#include "host/app/denoise_command.h"
#include "host/app/diff.h"
#include "host/app/merge_command.h"
#include "host/app/render_command.h"
#include "host/scene/sky_model.h"

// CLI11 is declared, not included: main.cpp and the Python module reach
// the parser through parse_command_line (docs/howto.md, "Build and test
// time"); a unit that calls CLI::App itself includes <CLI/CLI.hpp>.
namespace CLI {
class App;
}  // namespace CLI

namespace caustica {

struct GenerateArgs {
  int shapes = 400;
  bool spheres_only = false;
  uint32_t seed = 1;
  std::string output;
};

struct SkyArgs {
  SkyParams params;
  std::string output;
};

struct PlotArgs {
  std::vector<std::string> reports;
  std::string output;
};

// Options bind to the members: a Cli is never copied or moved (make_cli).
struct Cli {
 private:
  std::unique_ptr<CLI::App> owned_app_;

 public:
  CLI::App& app;
  RenderArgs render;
  MergeArgs merge;
  DenoiseArgs denoise;
  BenchArgs bench;
  GenerateArgs generate;
  SkyArgs sky;
  DiffArgs diff;
  PlotArgs plot;
  CLI::App *render_cmd = nullptr, *devices_cmd = nullptr, *merge_cmd = nullptr, *denoise_cmd = nullptr,
           *bench_cmd = nullptr, *generate_cmd = nullptr, *sky_cmd = nullptr, *diff_cmd = nullptr,
           *plot_cmd = nullptr;
  Cli();
  ~Cli();
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;
};

std::unique_ptr<Cli> make_cli();

// Parses argv into `cli`: -1 when a command is to run, else the exit
// status of what CLI11 already did (--help printed: 0; a parse error
// printed: its code). Callbacks' caustica::Error passes through.
int parse_command_line(Cli& cli, int argc, const char* const* argv);

// After a successful parse: the checks the chosen command makes before it
// reads a scene or an input, or renders (every option's value and the
// options' combinations); throws caustica::Error naming the option. The
// run below makes them again, as its first step.
void check_command_options(Cli& cli);

// Runs the parsed command; its exit status.
int run_command(Cli& cli);

}  // namespace caustica
