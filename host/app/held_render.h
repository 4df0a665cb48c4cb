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
// estimate; state() is the state file --checkpoint would write.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/app/error_report.h"
#include "host/app/render_command.h"
#include "host/image/image.h"
#include "host/render/integrator.h"
#include "host/render/render_state.h"

namespace caustica {

struct RenderRun;

// The film's passes besides the image, as named in an EXR's layers
// (host/app/film_outputs.h): what the film has, nothing else.
struct HeldPasses {
  std::optional<ImageF> beauty;  // the raw film, when the image is denoised
  std::optional<ImageF> albedo, normal;
  std::vector<float> depth;     // empty without the aux passes
  std::vector<float> variance;  // each pixel's estimated variance (times the exposure scale squared)
};

class HeldRender {
 public:
  // Renders `args` (RenderArgs::write_output false unless the caller wants
  // -o written) and keeps the result; throws what `caustica render` throws.
  explicit HeldRender(RenderArgs args);
  ~HeldRender();
  HeldRender(const HeldRender&) = delete;
  HeldRender& operator=(const HeldRender&) = delete;

  RenderMode mode() const;
  const ImageF& image() const { return image_; }
  int spp() const;  // the film's passes (binary and phong: 1)
  std::vector<uint32_t> pixel_spp() const;
  HeldPasses passes() const;
  // The film's own relMSE estimate (nullopt before 2 passes or without the
  // half buffer) and each pixel's share (their mean is the estimate).
  std::optional<double> error_estimate() const;
  std::vector<double> error_map() const;
  const RenderStats& stats() const;
  double seconds() const;  // since the first sample
  bool stopped_by_caller() const;
  const ErrorReport& report() const;
  // As `-o path` would have written it (with --denoise, --spp-map as given).
  void save(const std::string& path) const;
  // The state --checkpoint would write (path mode), its identity included.
  RenderState state() const;
  const RenderArgs& args() const { return args_; }
  std::string scene_path() const { return args_.session.scene_path; }

 private:
  RenderArgs args_;
  std::unique_ptr<RenderRun> run_;
  ImageF image_;
};

}  // namespace caustica
