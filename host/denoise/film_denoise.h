// A film's denoiser inputs and its denoised image's error (issue 37).
//
// Rules: everything is read from the film, never written to it. The
// colour is Film::mean() (the photon map's caustics included), the guides
// the film's albedo and normal passes. The guides are given as clean (OIDN's
// cleanAux) unless the scene makes them noisy in kind: a lens (depth of
// field) or smooth glass, whose paths split between reflection and
// refraction; then OIDN's models for noisy guides take them. Measured
// (docs/denoise.md): on the Cornell box clean guides win at every spp even
// where their own half-buffer estimate is high (the anti-aliased edges'
// noise, which the clean models tolerate), and on caustics.json the noisy
// models win even where it is low; cleaning the guides first (OIDN's
// prefiltering, three filter runs) came within a few percent of the better
// of the two at three times the cost (`--denoise-guides prefilter`,
// `caustica denoise --prefilter-guides`).
//
// The denoised image's error, estimated as its variance plus its bias
// squared, each summed relative to D(M)^2 + 0.01 and averaged as the
// colour's estimate is:
//  - variance: the film's passes [0, P) and [P, N) (its half buffer,
//    host/render/error_estimate.h) are two independent renders A and B of
//    n_A and n_B samples; each is denoised on its own, with its own halves
//    of the guides. If the denoised image's variance falls as c / n,
//    E[(D(A) - D(B))^2] = c (1/n_A + 1/n_B), so
//      Var(D(M)) ~ (D(A) - D(B))^2 n_A n_B / N^2.
//    This sees the noise the denoiser leaves, not its bias (detail smoothed
//    away, a caustic spread), which D(A) and D(B) share.
//  - bias: denoising moves the image by D(M) - M = b + r - n, n the raw
//    noise and r the part of it the denoiser leaves. Taking r = a n (a the
//    share it passes, a^2 = Var(D(M)) / Var(M), Var(M) the raw estimate),
//    E[(D(M) - M)^2] = b^2 + (1 - a)^2 Var(M), so b^2 is what the move holds
//    beyond the noise it removed (at least 0).
// Both rest on models: a denoiser's variance need not fall as 1 / n, r is
// not exactly a share of n, and at few samples the bias term is the small
// difference of two large, noisy ones (it then runs high). Measured against
// references in docs/denoise.md.
#pragma once

#include <optional>
#include <vector>

#include "host/denoise/denoiser.h"
#include "host/render/film.h"

namespace caustica {

struct FilmPasses {
  ImageF colour;
  std::optional<AuxImages> aux;  // with the film's aux passes
  std::vector<float> variance;   // each pixel's estimated variance (empty without a half buffer or 2 passes)
  std::optional<double> guide_noise;  // the guides' estimated relMSE (-v), where it can be measured
  GuideMode guides = GuideMode::Clean;  // how they are handed over (the rule above, or --denoise-guides)
};

// The guides' mode for a scene by the rule above: noisy with a lens or
// smooth glass, else clean.
inline GuideMode guide_mode_for(bool lens, bool smooth_glass) {
  return lens || smooth_glass ? GuideMode::Noisy : GuideMode::Clean;
}

FilmPasses read_film_passes(const Film& film, GuideMode guides = GuideMode::Clean);
// The colour denoised with the passes' guides (none without aux passes).
ImageF denoise_passes(const Denoiser& denoiser, const FilmPasses& passes);
// The rules above; nullopt without a half buffer or aux passes, or before
// two passes.
std::optional<double> estimate_denoised_rel_mse(const Denoiser& denoiser, const Film& film, const ImageF& denoised,
                                                GuideMode guides = GuideMode::Clean);

}  // namespace caustica
