#include "host/app/held_render.h"

#include "host/app/film_outputs.h"
#include "host/app/render_stages.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "host/render/error_estimate.h"
#include "host/render/film.h"
#include "host/render/renderer.h"

namespace caustica {
namespace {

ImageF scaled(ImageF image, float scale) {
  // As the .pfm and .exr writers multiply, value by value in float.
  for (float& v : image.rgb) v = v * scale;
  return image;
}

// Each pixel's estimated relMSE: its share of the film's point estimate
// (host/render/error_estimate.h), the photon map's own variance included,
// averaged over the channels.
// Of the image as written (times the exposure scale), as the monitor's.
std::vector<double> pixel_error_map(const Film& film, const ImageF& mean, const Film::SeparateError& separate,
                                    float exposure) {
  if (!film.has_half_buffer() || film.passes() < 2) return {};
  return pixel_rel_mse_estimate(mean, film.half_mean(), film.pixel_spp(), film.half_counts(), &separate.variance,
                                &separate.bias2, exposure);
}

}  // namespace

HeldRender::HeldRender(RenderArgs args) : args_(std::move(args)) {
  std::unique_ptr<RenderRun> run = render_scene(args_);
  if (!run->result) throw Error("render: no result on this rank");  // never: the module runs no ranks
  const RenderResult& result = *run->result;
  const Session& session = *run->plan.session;
  const Film& film = result.shown->film();
  mode_ = session.mode;
  display_ = run->plan.display;
  if (mode_ == RenderMode::Path) {
    passes_ = read_film_passes(film, run->plan.guides);
    // The main image of every output, as write_film_outputs makes it.
    if (run->plan.denoiser) denoised_ = denoise_passes(*run->plan.denoiser, passes_);
    image_ = scaled(denoised_ ? *denoised_ : passes_.colour, display_.exposure_scale);
    spp_ = film.passes();
    pixel_spp_ = film.pixel_spp();
    // The photon map's error, read once: for the error map and its own pass.
    const Film::SeparateError separate = film.separate_error();
    error_map_ = pixel_error_map(film, passes_.colour, separate, display_.exposure_scale);
    caustics_ = film.separate_image();
    if (caustics_) caustics_variance_ = separate.total();
    state_ = result.shown->state();
    state_->identity = render_identity(scene_hash(session.scene), session.mode, session.settings,
                                       bvh_quality_name(args_.session.bvh_quality));
  } else {
    unscaled_ = result.image;
    image_ = scaled(result.image, display_.exposure_scale);
    pixel_spp_.assign(image_.pixel_count(), 1u);
  }
  error_estimate_ = run->monitor->estimate();
  error_bound_ = run->monitor->bound();
  stats_ = run->stats;
  seconds_ = result.seconds;
  stopped_by_caller_ = run->stopped_by_caller;
  report_ = run->monitor->report();
  // `run` goes here: the session's device buffers, scene and film with it.
}

HeldPasses HeldRender::passes() const {
  HeldPasses out;
  if (mode_ != RenderMode::Path) return out;
  const float exposure = display_.exposure_scale;
  if (denoised_) out.beauty = scaled(passes_.colour, exposure);
  if (passes_.aux) {
    out.albedo = passes_.aux->albedo;
    out.normal = passes_.aux->normal;
    out.depth = passes_.aux->depth;
  }
  out.variance = passes_.variance;
  for (float& v : out.variance) v *= exposure * exposure;
  if (caustics_) {
    out.caustics = scaled(*caustics_, exposure);
    out.caustics_variance.resize(caustics_variance_.pixel_count());
    for (size_t p = 0; p < out.caustics_variance.size(); ++p) {
      const float* v = &caustics_variance_.rgb[3 * p];
      out.caustics_variance[p] = (v[0] + v[1] + v[2]) / 3.0f * exposure * exposure;
    }
  }
  return out;
}

void HeldRender::save(const std::string& path) const {
  check_output_image_path(path);
  if (mode_ != RenderMode::Path) return write_image(path, unscaled_, display_);
  FilmOutputOptions options;
  options.output = path;
  options.display = display_;
  write_pass_outputs(options, image_.width, image_.height, passes_, pixel_spp_, denoised_ ? &*denoised_ : nullptr);
}

const RenderState& HeldRender::state() const {
  if (!state_)
    throw Error("state: only path mode renders in passes that a state can hold and resume (binary and phong take one)");
  return *state_;
}

}  // namespace caustica
