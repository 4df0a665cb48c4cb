#include "host/app/held_render.h"

#include "host/app/render_stages.h"
#include "host/denoise/film_denoise.h"
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

}  // namespace

HeldRender::HeldRender(RenderArgs args) : args_(std::move(args)) {
  run_ = render_scene(args_);
  if (!run_->result) throw Error("render: no result on this rank");  // never: the module runs no ranks
  const RenderResult& result = *run_->result;
  const Film& film = result.shown->film();
  const float exposure = run_->plan.display.exposure_scale;
  if (mode() != RenderMode::Path) {
    image_ = scaled(result.image, exposure);
  } else if (run_->plan.denoiser) {
    // The main image of every output, as write_film_outputs makes it.
    image_ = scaled(denoise_passes(*run_->plan.denoiser, read_film_passes(film, run_->plan.guides)), exposure);
  } else {
    image_ = scaled(film.mean(), exposure);
  }
}

HeldRender::~HeldRender() = default;

RenderMode HeldRender::mode() const { return run_->plan.session->mode; }

int HeldRender::spp() const { return mode() == RenderMode::Path ? run_->result->shown->film().passes() : 1; }

std::vector<uint32_t> HeldRender::pixel_spp() const {
  if (mode() == RenderMode::Path) return run_->result->shown->film().pixel_spp();
  return std::vector<uint32_t>(image_.pixel_count(), 1u);
}

HeldPasses HeldRender::passes() const {
  HeldPasses out;
  if (mode() != RenderMode::Path) return out;
  const Film& film = run_->result->shown->film();
  const FilmPasses passes = read_film_passes(film, run_->plan.guides);
  const float exposure = run_->plan.display.exposure_scale;
  if (run_->plan.denoiser) out.beauty = scaled(passes.colour, exposure);
  if (passes.aux) {
    out.albedo = passes.aux->albedo;
    out.normal = passes.aux->normal;
    out.depth = passes.aux->depth;
  }
  out.variance = passes.variance;
  for (float& v : out.variance) v *= exposure * exposure;
  return out;
}

std::optional<double> HeldRender::error_estimate() const { return run_->monitor->estimate(); }

std::vector<double> HeldRender::error_map() const {
  if (mode() != RenderMode::Path) return {};
  const Film& film = run_->result->shown->film();
  if (!film.has_half_buffer() || film.passes() < 2) return {};
  const ImageF mean = film.mean();
  const ImageF separate = film.separate_variance();
  std::vector<double> map = pixel_rel_mse(mean, film.half_mean(), film.pixel_spp(), film.half_counts());
  // The photon map's own variance, as the film-wide estimate adds it
  // (host/render/error_estimate.h); then the mean over the channels.
  for (size_t p = 0; p < map.size(); ++p) {
    for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
      const double m = mean.rgb[i];
      map[p] += separate.rgb[i] / (m * m + kRelMseEpsilon);
    }
    map[p] /= 3.0;
  }
  return map;
}

const RenderStats& HeldRender::stats() const { return run_->stats; }
double HeldRender::seconds() const { return run_->result->seconds; }
bool HeldRender::stopped_by_caller() const { return run_->stopped_by_caller; }
const ErrorReport& HeldRender::report() const { return run_->monitor->report(); }

void HeldRender::save(const std::string& path) const {
  check_output_image_path(path);
  RenderArgs as_written = args_;
  as_written.output = path;
  RenderOutputs outputs(as_written, run_->plan);
  outputs.write_images(run_->result->image, run_->result->shown->film());
}

RenderState HeldRender::state() const {
  if (mode() != RenderMode::Path)
    throw Error("state: only path mode renders in passes that a state can hold and resume (binary and phong take one)");
  const Session& session = *run_->plan.session;
  RenderState state = run_->result->shown->state();
  state.identity = render_identity(scene_hash(session.scene), session.mode, session.settings,
                                   bvh_quality_name(args_.session.bvh_quality));
  return state;
}

}  // namespace caustica
