// `caustica denoise IN.exr -o OUT.exr`: Intel Open Image Denoise on any
// render's EXR that holds a colour and, ideally, albedo and normal layers
// (caustica's, Blender's, Mitsuba's: host/denoise/denoise_inputs.h names
// what is read), or on three files (--albedo, --normal). The output's R,
// G, B are the denoised colour; an .exr output also keeps the input colour
// as "beauty" and the guides as "albedo" and "normal", so it can be
// denoised again. Without guides it denoises the colour alone, and says so.
#pragma once

#include <string>

// CLI11 is declared, not included: it is parsed only by the units that
// add options (docs/howto.md, "Build and test time").
namespace CLI {
class App;
}  // namespace CLI

namespace caustica {

struct DenoiseArgs {
  std::string input, output, albedo, normal;
  std::string quality = "high";
  int threads = 0;          // 0: every core
  bool noisy_guides = false;      // --noisy-guides: OIDN's models for noisy guides
  bool prefilter_guides = false;  // --prefilter-guides: clean the guides first, then use them as clean
  bool quiet = false;
};

CLI::App* add_denoise_command(CLI::App& app, DenoiseArgs& args);
int run_denoise(const DenoiseArgs& args);

}  // namespace caustica
