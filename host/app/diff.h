// `caustica diff A B`: the error of image A against the reference B as MSE,
// relMSE, MAE and PSNR (host/image/metrics.h defines them), one line each and
// then one JSON object for scripts; optionally a false-colour heatmap of the
// per-pixel error. PFM and EXR are read as linear floats. Every other format
// (PNG, PPM, ...) is 8-bit and read as byte / 255 WITHOUT decoding the display
// gamma: such errors are in display units, not radiance, and the output says
// so. Images of different sizes are an error, never resampled.
#pragma once

#include <string>

#include "host/image/image.h"
#include "host/image/metrics.h"

namespace caustica {

struct DiffArgs {
  std::string image_path, reference_path;
  std::string heatmap_path;       // empty: no heatmap
  std::string metric = "relmse";  // of the heatmap: relmse, mse or mae
};

struct ImageFile {
  std::string path;
  ImageF image;
  bool eight_bit = false;  // read as byte / 255, not linear radiance
};

// One image as diff reads it (see the top of this file).
ImageFile read_image_for_diff(const std::string& path);

struct DiffPair {
  ImageFile image, reference;
};
// Both images; throws naming both files and both sizes when the sizes differ.
DiffPair read_diff_pair(const std::string& image_path, const std::string& reference_path);

// A PNG (or SVG) of the per-pixel error (metrics.h per_pixel_error) with a
// colour bar, drawn by gnuplot (host/app/gnuplot.h). The colour map is viridis
// on a log scale from the 1st to the 99.9th percentile of the positive finite
// per-pixel errors, widened to whole decades so that both ends carry a tick
// label; values outside (zero error below, infinite error above) take the end
// colours. With no positive finite error at all (identical images) the range
// is 1e-6..1. `title` is drawn above the image verbatim.
void write_error_heatmap(const ImageF& image, const ImageF& reference, ErrorMetric metric,
                         const std::string& out_path, const std::string& title = "");

// The subcommand: prints the metrics to stdout, returns the exit status.
int run_diff(const DiffArgs& args);

}  // namespace caustica
