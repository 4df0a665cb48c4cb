// What a render of part of the work may do: `--passes START:END` (one
// process, a part for `caustica merge`), which refuses adaptive sampling
// and the photon pass (neither is a sum of passes: render_options.cpp and
// render_command.cpp say why), and a render under mpirun with several ranks
// (host/app/distributed_render.h), which shares every wave and so takes
// every option but --passes (docs/distributed.md).
#include <cctype>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "host/app/render_command.h"
#include "host/error.h"

namespace caustica {

std::pair<int, int> parse_pass_range(const std::string& text) {
  const size_t colon = text.find(':');
  auto whole = [&](const std::string& part, long long& value) {
    char* end = nullptr;
    value = part.empty() || !std::isdigit(static_cast<unsigned char>(part[0])) ? -1 : std::strtoll(part.c_str(), &end, 10);
    return value >= 0 && end && *end == '\0' && value <= std::numeric_limits<int32_t>::max();
  };
  long long first = 0, end = 0;
  if (colon == std::string::npos || !whole(text.substr(0, colon), first) || !whole(text.substr(colon + 1), end) ||
      end <= first)
    throw Error("--passes '" + text + "': expected START:END, whole numbers with 0 <= START < END (passes [START, END))");
  return {int(first), int(end)};
}

// "mpirun with N ranks", for errors.
std::string ranks_text(const RenderArgs& a) {
  return "mpirun with " + std::to_string(a.ranks->size()) + " ranks";
}

// What a distributed render does not do (yet), refused before anything is
// read; and each rank's device and voice.
void check_distributed_options(RenderArgs& a) {
  const std::string ranks = ranks_text(a);
  auto refuse = [&](bool given, const std::string& option, const std::string& why) {
    if (given) throw Error(ranks + ": " + option + " " + why + " (docs/distributed.md)");
  };
  refuse(!a.passes.empty(), "--passes", "is for one process: the ranks split the passes themselves");
  // --device A,B,...: rank with local rank L takes entry L mod count.
  const std::string& spec = a.session.device;
  if (spec.find(',') != std::string::npos) {
    std::vector<std::string> entries;
    for (size_t at = 0;;) {
      const size_t comma = spec.find(',', at);
      entries.push_back(spec.substr(at, comma - at));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    a.session.device = entries[size_t(a.ranks->local_rank()) % entries.size()];
  }
  // Progress, the report and every message come from rank 0 only.
  // Rank 0 alone reads a resumed state and writes checkpoints (of the
  // summed film).
  if (a.ranks->rank() != 0) {
    a.checkpoint.clear();
    a.checkpoint_every_s.reset();
    a.resume.clear();
    a.quiet = true;
    a.verbose = false;
    a.report.clear();
    a.plot.clear();
  }
}

}  // namespace caustica
