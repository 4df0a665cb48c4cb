// A render kept in memory: what the Python module's caustica.render
// returns (python/caustica_module.cpp). It runs exactly what `caustica
// render` runs (render_scene: the same options, checks, plan, render and
// error monitor), then answers questions about the result instead of
// writing files: the image as an HDR output holds it, the film's passes,
// its error estimate and report, its state, and writes any output format
// on request. The Python layer converts these to NumPy arrays and dicts
// and holds no rendering logic.
//
// Rules: image() has the bits of the .pfm that `caustica render` with the
// same options writes (the main image, denoised with --denoise, times the
// exposure scale); error_map() averages to the film's own relMSE
// estimate; state() is the state file --checkpoint would write. Once
// rendered, everything is read back to the host and the session (device
// buffers, scene, film) is released: a Render holds its images, passes and
// state (the film's sums, 48 bytes a pixel and value), not a device.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "host/app/error_report.h"
#include "host/app/render_command.h"
#include "host/denoise/film_denoise.h"
#include "host/image/tonemap.h"
#include "host/image/image.h"
#include "host/render/integrator.h"
#include "host/render/render_state.h"

namespace caustica {

// The film's passes besides the image, as named in an EXR's layers
// (host/app/film_outputs.h): what the film has, nothing else.
struct HeldPasses {
  std::optional<ImageF> beauty;  // the raw film, when the image is denoised
  std::optional<ImageF> albedo, normal;
  std::vector<float> depth;     // empty without the aux passes
  std::vector<float> variance;  // each pixel's estimated variance (times the exposure scale squared)
  // With the photon pass: its caustic radiance (a part of the image, times
  // the exposure scale) and that estimate's own variance (its noise and
  // squared bias, a part of `variance`), to tell the two estimators'
  // errors apart (docs/error.md).
  std::optional<ImageF> caustics;
  std::vector<float> caustics_variance;
};

class HeldRender {
 public:
  // Renders `args` (RenderArgs::write_output false unless the caller wants
  // -o written) and keeps the result; throws what `caustica render` throws.
  explicit HeldRender(RenderArgs args);

  RenderMode mode() const { return mode_; }
  const ImageF& image() const { return image_; }
  int spp() const { return spp_; }  // the film's passes (binary and phong: 1)
  const std::vector<uint32_t>& pixel_spp() const { return pixel_spp_; }
  HeldPasses passes() const;
  // The film's own relMSE estimate (nullopt before 2 passes or without the
  // half buffer) and each pixel's share (their mean is the estimate).
  const std::optional<double>& error_estimate() const { return error_estimate_; }
  const std::optional<double>& error_bound() const { return error_bound_; }  // its 90% upper bound
  const std::vector<double>& error_map() const { return error_map_; }
  const RenderStats& stats() const { return stats_; }
  double seconds() const { return seconds_; }  // since the first sample
  bool stopped_by_caller() const { return stopped_by_caller_; }
  const ErrorReport& report() const { return report_; }
  // The image as `-o path` writes it (.exr: with the film's passes).
  void save(const std::string& path) const;
  // The state --checkpoint would write (path mode), its identity included.
  const RenderState& state() const;
  const RenderArgs& args() const { return args_; }

 private:
  RenderArgs args_;
  RenderMode mode_ = RenderMode::Phong;
  DisplaySettings display_;
  ImageF image_;                   // the main image times the exposure
  ImageF unscaled_;                // binary and phong: the image as rendered
  FilmPasses passes_;              // path: colour (the film's mean), aux, variance
  std::optional<ImageF> denoised_;  // path with --denoise: the main image
  int spp_ = 1;
  std::vector<uint32_t> pixel_spp_;
  std::optional<double> error_estimate_, error_bound_;
  std::optional<ImageF> caustics_;  // the photon map's caustic radiance and its variance (HeldPasses)
  ImageF caustics_variance_;
  std::vector<double> error_map_;
  RenderStats stats_;
  double seconds_ = 0.0;
  bool stopped_by_caller_ = false;
  ErrorReport report_;
  std::optional<RenderState> state_;
};

}  // namespace caustica
