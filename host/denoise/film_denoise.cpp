#include "host/denoise/film_denoise.h"

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

FilmPasses read_film_passes(const Film& film) {
  FilmPasses passes;
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
  DenoiseGuides guides;
  if (passes.aux) {
    guides.albedo = &passes.aux->albedo;
    guides.normal = &passes.aux->normal;
    guides.clean = passes.guides_clean();
  }
  return denoiser.denoise(passes.colour, guides);
}

std::optional<double> estimate_denoised_rel_mse(const Denoiser& denoiser, const Film& film, const ImageF& denoised) {
  if (!film.has_half_buffer() || !film.has_aux_passes() || film.passes() < 2) return std::nullopt;
  const std::vector<uint32_t>& spp = film.pixel_spp();
  const std::vector<uint32_t> half_counts = film.half_counts();
  const ImageF mean = film.mean(), half_b = film.half_mean();
  const AuxImages aux = film.aux_mean(), aux_b = film.aux_half_mean();
  const ImageF half_a = other_half(mean, half_b, spp, half_counts);
  const AuxImages aux_a = other_half(aux, aux_b, spp, half_counts);
  // Each half's guides are as noisy as its samples: cleaned unless the
  // whole film's are clean.
  const bool clean =
      estimated_rel_mse(aux.albedo, aux_b.albedo, spp, half_counts) +
          estimated_rel_mse(aux.normal, aux_b.normal, spp, half_counts) <=
      kNoisyGuideRelMse;
  const ImageF da = denoiser.denoise(half_a, {&aux_a.albedo, &aux_a.normal, clean});
  const ImageF db = denoiser.denoise(half_b, {&aux_b.albedo, &aux_b.normal, clean});
  double sum = 0.0;
  for (size_t p = 0; p < spp.size(); ++p) {
    const double n = spp[p], b = half_counts[p], a = n - b;
    if (b == 0 || a <= 0) continue;
    const double weight = a * b / (n * n);
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double d = double(da.rgb[i]) - db.rgb[i], m = denoised.rgb[i];
      sum += d * d * weight / (m * m + kRelMseEpsilon);
    }
  }
  return denoised.rgb.empty() ? 0.0 : sum / double(denoised.rgb.size());
}

}  // namespace caustica
