// `caustica merge A.cst B.cst ... [-o IMAGE] [--state OUT.cst]`: adds render
// states of disjoint passes (host/render/state_merge.h) into one state
// and/or its image, with the same bits as one render of the union of their
// passes. The image is the film's linear radiance (.pfm or .exr, times
// 2^--exposure); `caustica render SCENE --spp N --resume OUT.cst -o x.png`
// draws a merged state of passes [0, N) with the scene's display settings.
#pragma once

#include <string>
#include <vector>

// CLI11 is declared, not included: it is parsed only by the units that
// add options (docs/howto.md, "Build and test time").
namespace CLI {
class App;
}  // namespace CLI

namespace caustica {

struct MergeArgs {
  std::vector<std::string> states;
  std::string output;  // an image (.pfm or .exr)
  std::string state;   // the merged state
  double exposure_stops = 0.0;
  bool quiet = false;
};

CLI::App* add_merge_command(CLI::App& app, MergeArgs& args);
int run_merge(const MergeArgs& args);

}  // namespace caustica
