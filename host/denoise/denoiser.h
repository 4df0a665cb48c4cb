// Denoising with Intel Open Image Denoise (OIDN): its "RT" filter on a
// linear HDR image, guided by the film's albedo and normal passes
// (host/render/film.h). The library is linked where CMake found it
// (cmake/FindOIDN.cmake: tools/fetch_oidn.sh's copy of the pinned pyoidn
// wheel's libraries, or a system OIDN); without it everything here builds,
// available() is false and a Denoiser cannot be made: its constructor
// throws missing_message(), one line saying how to get the library.
//
// Rules: denoising reads images and writes a new one; it never touches the
// film, so a render's bits (and its state files) are the same with or
// without it, and the same film denoises to the same image. OIDN's CPU
// device runs at most DenoiserOptions::threads threads (the render's).
#pragma once

#include <memory>
#include <string>

#include "host/image/image.h"

namespace caustica {

enum class DenoiseQuality { Fast, Balanced, High };
// "fast", "balanced" or "high"; anything else throws caustica::Error.
DenoiseQuality parse_denoise_quality(const std::string& name);
const char* denoise_quality_name(DenoiseQuality quality);

struct DenoiserOptions {
  DenoiseQuality quality = DenoiseQuality::High;
  int threads = 0;     // the CPU device's most threads; 0: OIDN's own choice (every core)
  bool gpu = false;    // try OIDN's CUDA device first (the render runs on a GPU)
};

// The guides that go with a colour image: both or neither (OIDN takes a
// normal only with an albedo). clean: they are (nearly) noise-free, as a
// pinhole camera's first rough surfaces are (OIDN's cleanAux). Otherwise,
// with prefilter they are denoised first (OIDN's recommended prefiltering,
// three filter runs) and then given as clean; without, the colour filter is
// told they are noisy (its models for noisy guides).
struct DenoiseGuides {
  const ImageF* albedo = nullptr;
  const ImageF* normal = nullptr;
  bool clean = true;
  bool prefilter = true;
};

// How a render's guides are handed over (--denoise-guides): as clean, as
// noisy (OIDN's models for noisy guides), or cleaned first (prefilter).
enum class GuideMode { Clean, Noisy, Prefilter };
// "clean", "noisy" or "prefilter"; anything else throws caustica::Error.
GuideMode parse_guide_mode(const std::string& name);
const char* guide_mode_name(GuideMode mode);
inline DenoiseGuides guides_for(GuideMode mode, const ImageF* albedo, const ImageF* normal) {
  return {albedo, normal, mode == GuideMode::Clean, mode == GuideMode::Prefilter};
}

class Denoiser {
 public:
  static bool available();
  static std::string missing_message();
  explicit Denoiser(const DenoiserOptions& options);
  ~Denoiser();
  Denoiser(const Denoiser&) = delete;
  Denoiser& operator=(const Denoiser&) = delete;

  // The denoised colour (same size). Throws caustica::Error with OIDN's
  // message if it fails, or if a guide's size is not the colour's.
  ImageF denoise(const ImageF& colour, const DenoiseGuides& guides = {}) const;
  // "OIDN 2.5.1 CPU, 2 threads, quality high", and why not CUDA where asked.
  const std::string& description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustica
