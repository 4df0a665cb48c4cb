// Fuzz target: the command line (host/app/cli.h). The input is an argument
// list, one argument per line, the subcommand first; it is parsed exactly
// as main() parses it, then the chosen command's checks run (those made
// before it reads a scene or renders: every option's value and their
// combinations). The contract: a list is accepted or refused with
// CLI11's parse error or a caustica::Error; an accepted render holds only
// finite numbers in range, and no option names the output as the state.
// Anything else (a crash, a sanitizer report, another exception) is a
// finding. Nothing is rendered and no file is written (an accepted list's
// files are never opened for writing here).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/app/cli.h"
#include "host/error.h"

namespace {

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz_cli: accepted, but %s\n", what);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args{"caustica"};
  std::string current;
  for (size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current += char(data[i]);
    }
  }
  if (!current.empty()) args.push_back(current);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  const std::unique_ptr<caustica::Cli> cli = caustica::make_cli();
  try {
    cli->app.parse(int(argv.size()), argv.data());
    caustica::check_command_options(*cli);
  } catch (const CLI::Error&) {
    return 0;
  } catch (const caustica::Error&) {
    return 0;
  }
  if (cli->render_cmd->parsed()) {
    const caustica::RenderArgs& r = cli->render;
    const caustica::SessionOptions& s = r.session;
    require(std::isfinite(s.time_limit_s) && s.time_limit_s >= 0.0, "--time is not a finite non-negative time");
    require(std::isfinite(r.write_every_s) && r.write_every_s >= 0.0, "--write-every is not finite");
    require(std::isfinite(r.target_error) && r.target_error >= 0.0, "--target-error is not finite");
    require(!r.checkpoint_every_s || (std::isfinite(*r.checkpoint_every_s) && *r.checkpoint_every_s > 0.0),
            "--checkpoint-every is not a finite positive time");
    require(!r.exposure || std::isfinite(*r.exposure), "--exposure is not finite");
    require(!r.gamma || (std::isfinite(*r.gamma) && *r.gamma > 0.0f), "--gamma is not finite and positive");
    require(std::isfinite(s.caustic_radius) && s.caustic_radius >= 0.0f, "--caustic-radius is not finite");
    require(s.spp >= 0 && s.first_pass >= 0 && (s.first_pass == 0 || s.first_pass < s.spp),
            "the pass range is not a range");
    require(r.checkpoint.empty() || r.checkpoint != r.output, "the checkpoint is the output image");
  }
  if (cli->sky_cmd->parsed()) {
    const caustica::SkyParams& p = cli->sky.params;
    require(std::isfinite(p.sun_elevation) && std::isfinite(p.sun_azimuth) && std::isfinite(p.turbidity),
            "a sky parameter is not finite");
  }
  return 0;
}
