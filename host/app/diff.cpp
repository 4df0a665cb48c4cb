#include "host/app/diff.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "host/app/gnuplot.h"
#include "host/error.h"
#include "host/image/image_io.h"

namespace caustica {
namespace {

std::string size_str(const ImageF& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }

const char* metric_label(ErrorMetric m) {
  switch (m) {
    case ErrorMetric::Mse: return "MSE";
    case ErrorMetric::RelMse: return "relMSE";
    case ErrorMetric::Mae: return "MAE";
  }
  return "?";
}

struct LogRange {
  double lo, hi;
};

// See write_error_heatmap in diff.h.
LogRange heatmap_range(const std::vector<double>& errors) {
  std::vector<double> positive;
  positive.reserve(errors.size());
  for (double e : errors)
    if (e > 0.0 && std::isfinite(e)) positive.push_back(e);
  if (positive.empty()) return {1e-6, 1.0};
  auto percentile = [&](double q) {
    auto it = positive.begin() + static_cast<ptrdiff_t>(q * (positive.size() - 1));
    std::nth_element(positive.begin(), it, positive.end());
    return *it;
  };
  const double p_lo = percentile(0.01), p_hi = percentile(0.999);
  const double lo = std::pow(10.0, std::floor(std::log10(p_lo)));
  double hi = std::pow(10.0, std::ceil(std::log10(p_hi)));
  if (hi <= lo) hi = lo * 10.0;  // every error the same power of ten
  return {lo, hi};
}

}  // namespace

ImageFile read_image_for_diff(const std::string& path) {
  ImageFile file;
  file.path = path;
  if (is_hdr_path(path)) {
    file.image = read_hdr_image(path);
    return file;
  }
  const Image8 bytes = read_image8(path);
  file.eight_bit = true;
  file.image = ImageF(bytes.width, bytes.height);
  for (size_t i = 0; i < bytes.rgb.size(); ++i) file.image.rgb[i] = bytes.rgb[i] / 255.0f;
  return file;
}

DiffPair read_diff_pair(const std::string& image_path, const std::string& reference_path) {
  DiffPair pair{read_image_for_diff(image_path), read_image_for_diff(reference_path)};
  const ImageF &a = pair.image.image, &b = pair.reference.image;
  if (a.width != b.width || a.height != b.height)
    throw Error("cannot compare '" + image_path + "' (" + size_str(a) + ") with the reference '" + reference_path +
                "' (" + size_str(b) + "): the sizes differ");
  return pair;
}

void write_error_heatmap(const ImageF& image, const ImageF& reference, ErrorMetric metric,
                         const std::string& out_path, const std::string& title) {
  const std::vector<double> errors = per_pixel_error(image, reference, metric);
  if (errors.empty()) throw Error("cannot draw '" + out_path + "': the images are empty");
  const LogRange range = heatmap_range(errors);

  // Clamped into the colour range: a log axis cannot place 0, and infinite
  // error should read as "worst", not vanish.
  std::vector<float> clamped(errors.size());
  for (size_t i = 0; i < errors.size(); ++i)
    clamped[i] = static_cast<float>(std::clamp(errors[i], range.lo, range.hi));
  ColourBar bar;
  bar.lo = range.lo;
  bar.hi = range.hi;
  bar.log_scale = true;
  bar.tic_format = "10^{%T}";
  bar.label = std::string(metric_label(metric)) + " per pixel";
  draw_heatmap(clamped, image.width, image.height, bar, title, out_path);
}

int run_diff(const DiffArgs& args) {
  const ErrorMetric heatmap_metric = parse_error_metric(args.metric);
  const DiffPair pair = read_diff_pair(args.image_path, args.reference_path);
  const ImageF &a = pair.image.image, &ref = pair.reference.image;
  const double e_mse = mse(a, ref), e_relmse = rel_mse(a, ref), e_mae = mean_abs_error(a, ref);
  const double e_psnr = psnr(a, ref);

  std::printf("image      %s (%s, %s)\n", pair.image.path.c_str(), size_str(a).c_str(),
              pair.image.eight_bit ? "8-bit" : "linear float");
  std::printf("reference  %s (%s, %s)\n", pair.reference.path.c_str(), size_str(ref).c_str(),
              pair.reference.eight_bit ? "8-bit" : "linear float");
  if (pair.image.eight_bit || pair.reference.eight_bit)
    std::printf("note: 8-bit images are read as byte / 255 without undoing their display gamma or tone curve, "
                "so these errors are in display units, not linear radiance\n");
  std::printf("MSE        %.6g\n", e_mse);
  std::printf("relMSE     %.6g   (eps %g)\n", e_relmse, kRelMseEpsilon);
  std::printf("MAE        %.6g\n", e_mae);
  std::printf("PSNR       %.4g dB   (peak %.6g: the reference's largest value)\n", e_psnr, psnr_peak(ref));

  if (!args.heatmap_path.empty()) {
    write_error_heatmap(a, ref, heatmap_metric, args.heatmap_path,
                        std::string(metric_label(heatmap_metric)) + " of " + pair.image.path + " against " +
                            pair.reference.path);
    std::printf("heatmap    %s (%s per pixel, log scale)\n", args.heatmap_path.c_str(), metric_label(heatmap_metric));
  }
  // JSON has no infinity: non-finite values are written as null.
  nlohmann::ordered_json j = {{"mse", e_mse}, {"relmse", e_relmse}, {"mae", e_mae}, {"psnr", e_psnr}};
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace caustica
