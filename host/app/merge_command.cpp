#include "host/app/merge_command.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "host/app/cli_numbers.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/limits.h"
#include "host/render/state_merge.h"
#include "host/app/film_outputs.h"

namespace caustica {

CLI::App* add_merge_command(CLI::App& app, MergeArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "merge", "add render states of disjoint passes (render --passes ... --checkpoint) into one state or image");
  cmd->add_option("states", a.states, "render state files (--checkpoint), of disjoint passes")->required();
  cmd->add_option("-o,--output", a.output, "the merged image: the film's linear radiance (.pfm or .exr)");
  cmd->add_option("--state", a.state, "the merged render state (resume or merge it further)");
  cmd->add_option("--exposure", a.exposure_stops, "scale the image by 2^STOPS (default 0)")
      ->check(finite_range(-limits::kMaxExposureStops, limits::kMaxExposureStops));
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_merge(const MergeArgs& a) {
  if (a.output.empty() && a.state.empty())
    throw Error("merge: nothing to write: give -o IMAGE (.pfm or .exr) and/or --state FILE");
  if (!a.output.empty()) {
    check_output_image_path(a.output);
    if (!is_hdr_path(a.output))
      throw Error("merge -o " + a.output + ": expected a linear .pfm or .exr image (for a display image resume the "
                  "merged --state with `caustica render SCENE --resume`)");
  }
  std::vector<NamedState> states;
  for (const std::string& path : a.states) states.push_back({path, read_render_state(path)});
  const RenderState merged = merge_render_states(states);
  if (!a.state.empty()) write_render_state(a.state, merged);
  if (!a.output.empty()) {
    const std::string& first = states.front().path;
    const int width = std::atoi(identity_value(first, merged.identity, "width").c_str());
    const int height = std::atoi(identity_value(first, merged.identity, "height").c_str());
    if (width <= 0 || height <= 0)
      throw Error(first + ": a state of a " + std::to_string(width) + "x" + std::to_string(height) + " image");
    const ImageF image = film_state_mean(merged.film, width, height);
    const float exposure = float(std::exp2(a.exposure_stops));
    if (lower_extension(a.output) == ".exr") {
      // With the aux passes where the states hold them (film_outputs.h's layers).
      FilmPasses passes;
      passes.colour = image;
      passes.aux = film_state_aux_mean(merged.film, width, height);
      write_exr_planes(a.output, width, height, film_pass_planes(passes, merged.film.spp, exposure, nullptr));
    }
    else write_image(a.output, image, DisplaySettings{ToneMap::Linear, exposure, 1.0f});
  }
  if (!a.quiet)
    std::fprintf(stderr, "[caustica] merged %zu states: %s, %d spp%s%s%s%s\n", states.size(),
                 merged.film.held.describe().c_str(), merged.film.passes, a.output.empty() ? "" : ", wrote ",
                 a.output.c_str(), a.state.empty() ? "" : ", wrote ", a.state.c_str());
  return 0;
}

}  // namespace caustica
