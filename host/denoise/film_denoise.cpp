#include "host/denoise/film_denoise.h"

#include <algorithm>
#include <cmath>

#include "host/image/metrics.h"
#include "host/render/error_estimate.h"

namespace caustica {
namespace {

// The passes not in the half: each pixel's (N M - n_B B) / n_A (a pixel
// without a half: its mean).
ImageF other_half(const ImageF& mean, const ImageF& half, const std::vector<uint32_t>& spp,
                  const std::vector<uint32_t>& half_counts) {
  ImageF out = mean;
  for (size_t p = 0; p < spp.size(); ++p) {
    const uint32_t n = spp[p], b = half_counts[p];
    if (b == 0 || b >= n) continue;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i)
      out.rgb[i] = float((double(n) * mean.rgb[i] - double(b) * half.rgb[i]) / double(n - b));
  }
  return out;
}

AuxImages other_half(const AuxImages& mean, const AuxImages& half, const std::vector<uint32_t>& spp,
                     const std::vector<uint32_t>& half_counts) {
  AuxImages out;
  out.albedo = other_half(mean.albedo, half.albedo, spp, half_counts);
  out.normal = other_half(mean.normal, half.normal, spp, half_counts);
  out.depth = mean.depth;
  return out;
}

}  // namespace

FilmPasses read_film_passes(const Film& film, GuideMode guides) {
  FilmPasses passes;
  passes.guides = guides;
  passes.colour = film.mean();
  const bool halves = film.has_half_buffer() && film.passes() >= 2;
  if (halves) {
    const ImageF separate = film.separate_variance();
    passes.variance =
        pixel_variance(passes.colour, film.half_mean(), film.pixel_spp(), film.half_counts(), &separate);
  }
  if (film.has_aux_passes() && film.passes() > 0) {
    passes.aux = film.aux_mean();
    if (halves) {
      const AuxImages half = film.aux_half_mean();
      passes.guide_noise =
          estimated_rel_mse(passes.aux->albedo, half.albedo, film.pixel_spp(), film.half_counts()) +
          estimated_rel_mse(passes.aux->normal, half.normal, film.pixel_spp(), film.half_counts());
    }
  }
  return passes;
}

ImageF denoise_passes(const Denoiser& denoiser, const FilmPasses& passes) {
  if (!passes.aux) return denoiser.denoise(passes.colour);
  return denoiser.denoise(passes.colour, guides_for(passes.guides, &passes.aux->albedo, &passes.aux->normal));
}

std::optional<double> estimate_denoised_rel_mse(const Denoiser& denoiser, const Film& film, const ImageF& denoised,
                                                GuideMode guides) {
  if (!film.has_half_buffer() || !film.has_aux_passes() || film.passes() < 2) return std::nullopt;
  const std::vector<uint32_t>& spp = film.pixel_spp();
  const std::vector<uint32_t> half_counts = film.half_counts();
  const ImageF mean = film.mean(), half_b = film.half_mean();
  const AuxImages aux = film.aux_mean(), aux_b = film.aux_half_mean();
  const ImageF half_a = other_half(mean, half_b, spp, half_counts);
  const AuxImages aux_a = other_half(aux, aux_b, spp, half_counts);
  // Each half denoised as the whole film is.
  const ImageF da = denoiser.denoise(half_a, guides_for(guides, &aux_a.albedo, &aux_a.normal));
  const ImageF db = denoiser.denoise(half_b, guides_for(guides, &aux_b.albedo, &aux_b.normal));
  // Three sums over pixels and channels, each relative to D(M)^2 + eps:
  // the denoised image's variance, the raw image's, and how far denoising
  // moved the image.
  double residual = 0.0, raw = 0.0, change = 0.0;
  for (size_t p = 0; p < spp.size(); ++p) {
    const double n = spp[p], b = half_counts[p], a = n - b;
    if (b == 0 || a <= 0) continue;
    const double weight = a * b / (n * n), raw_weight = b / a;
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double d = double(da.rgb[i]) - db.rgb[i], dm = denoised.rgb[i];
      const double to = 1.0 / (dm * dm + kRelMseEpsilon);
      const double m = mean.rgb[i], h = double(m) - half_b.rgb[i], moved = dm - m;
      residual += d * d * weight * to;
      raw += h * h * raw_weight * to;
      change += moved * moved * to;
    }
  }
  // The bias: D(M) - M = b + r - n with n the raw noise and r what of it
  // the denoiser leaves; with r = a n (a the share passed through),
  // E[(D(M) - M)^2] = b^2 + (1 - a)^2 Var(M) and a^2 = Var(D) / Var(M).
  const double share = raw > 0.0 ? std::sqrt(std::min(1.0, residual / raw)) : 0.0;
  const double bias = std::max(0.0, change - (1.0 - share) * (1.0 - share) * raw);
  return denoised.rgb.empty() ? 0.0 : (residual + bias) / double(denoised.rgb.size());
}

}  // namespace caustica
