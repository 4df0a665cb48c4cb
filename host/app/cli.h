// The command line: every subcommand's options (CLI11), bound to their
// argument structs, and the dispatch to the command that runs. main()
// parses with it under mpirun's set-up and its error handling; the fuzz
// target fuzz/fuzz_cli.cpp parses arbitrary argument lists with it and
// runs the checks each command makes before it reads or renders anything.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

#include "host/app/bench.h"
#include "host/app/denoise_command.h"
#include "host/app/diff.h"
#include "host/app/merge_command.h"
#include "host/app/render_command.h"
#include "host/scene/sky_model.h"

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
  CLI::App app{"caustica: an OpenCL wavefront renderer for the coursework scene format"};
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
  Cli() = default;
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;
};

std::unique_ptr<Cli> make_cli();

// After a successful parse: the checks the chosen command makes before it
// reads a scene or an input, or renders (every option's value and the
// options' combinations); throws caustica::Error naming the option. The
// run below makes them again, as its first step.
void check_command_options(Cli& cli);

// Runs the parsed command; its exit status.
int run_command(Cli& cli);

}  // namespace caustica
