#include "host/denoise/denoiser.h"

#include <cstdlib>
#include <vector>

#include "host/error.h"

#ifdef CAUSTICA_WITH_OIDN
#include "host/denoise/oidn_api.h"
#endif

namespace caustica {

DenoiseQuality parse_denoise_quality(const std::string& name) {
  if (name == "fast") return DenoiseQuality::Fast;
  if (name == "balanced") return DenoiseQuality::Balanced;
  if (name == "high") return DenoiseQuality::High;
  throw Error("--denoise-quality '" + name + "': expected fast, balanced or high");
}

const char* denoise_quality_name(DenoiseQuality quality) {
  switch (quality) {
    case DenoiseQuality::Fast: return "fast";
    case DenoiseQuality::Balanced: return "balanced";
    case DenoiseQuality::High: return "high";
  }
  return "?";
}

GuideMode parse_guide_mode(const std::string& name) {
  if (name == "clean") return GuideMode::Clean;
  if (name == "noisy") return GuideMode::Noisy;
  if (name == "prefilter") return GuideMode::Prefilter;
  throw Error("--denoise-guides '" + name + "': expected auto, clean, noisy or prefilter");
}

const char* guide_mode_name(GuideMode mode) {
  switch (mode) {
    case GuideMode::Clean: return "clean";
    case GuideMode::Noisy: return "noisy";
    case GuideMode::Prefilter: return "cleaned first (prefilter)";
  }
  return "?";
}

namespace {
// CAUSTICA_NO_OIDN=1: behave as a build without the library (what the
// tests check of that build's message, and comparisons without it).
bool disabled_by_environment() {
  const char* v = std::getenv("CAUSTICA_NO_OIDN");
  return v && *v && std::string(v) != "0";
}
}  // namespace

std::string Denoiser::missing_message() {
  return "denoising needs Intel Open Image Denoise, which this caustica was built without: run tools/fetch_oidn.sh "
         "(it fetches the pinned pyoidn 2.5.1.0 wheel's libraries with pip into .deps/), then "
         "`cmake -S . -B build && cmake --build build` (or ./caustica test)";
}

#ifndef CAUSTICA_WITH_OIDN

struct Denoiser::Impl {};
bool Denoiser::available() { return false; }
Denoiser::Denoiser(const DenoiserOptions&) { throw Error(missing_message()); }
Denoiser::~Denoiser() = default;
ImageF Denoiser::denoise(const ImageF&, const DenoiseGuides&) const { throw Error(missing_message()); }
const std::string& Denoiser::description() const {
  static const std::string none = "none";
  return none;
}

#else

bool Denoiser::available() { return !disabled_by_environment(); }

namespace {

OIDNQuality oidn_quality(DenoiseQuality q) {
  switch (q) {
    case DenoiseQuality::Fast: return OIDN_QUALITY_FAST;
    case DenoiseQuality::Balanced: return OIDN_QUALITY_BALANCED;
    case DenoiseQuality::High: return OIDN_QUALITY_HIGH;
  }
  return OIDN_QUALITY_DEFAULT;
}

// The device's pending error as a caustica::Error (nothing if none).
void throw_if_failed(OIDNDevice device, const std::string& doing) {
  const char* message = nullptr;
  const OIDNError code = oidnGetDeviceError(device, &message);
  if (code != OIDN_ERROR_NONE)
    throw Error("Open Image Denoise: " + doing + " failed: " + (message ? message : "error " + std::to_string(code)));
}

// A device, committed, or nullptr with the reason in *why.
OIDNDevice new_device(OIDNDeviceType type, int threads, std::string* why) {
  OIDNDevice device = oidnNewDevice(type);
  if (!device) {
    const char* message = nullptr;
    oidnGetDeviceError(nullptr, &message);
    *why = message ? message : "no such device";
    return nullptr;
  }
  if (type == OIDN_DEVICE_TYPE_CPU && threads > 0) oidnSetDeviceInt(device, "numThreads", threads);
  oidnCommitDevice(device);
  const char* message = nullptr;
  if (oidnGetDeviceError(device, &message) != OIDN_ERROR_NONE) {
    *why = message ? message : "the device could not be set up";
    oidnReleaseDevice(device);
    return nullptr;
  }
  return device;
}

// An image in a device buffer (three floats a pixel).
struct DeviceImage {
  OIDNBuffer buffer = nullptr;
  size_t bytes = 0;
  DeviceImage(OIDNDevice device, size_t pixels) : bytes(pixels * 3 * sizeof(float)) {
    buffer = oidnNewBuffer(device, bytes);
    throw_if_failed(device, "allocating an image buffer");
  }
  ~DeviceImage() {
    if (buffer) oidnReleaseBuffer(buffer);
  }
  DeviceImage(const DeviceImage&) = delete;
  DeviceImage& operator=(const DeviceImage&) = delete;
  void write(const ImageF& image) { oidnWriteBuffer(buffer, 0, bytes, image.rgb.data()); }
  void read(ImageF& image) const { oidnReadBuffer(buffer, 0, bytes, image.rgb.data()); }
};

}  // namespace

struct Denoiser::Impl {
  OIDNDevice device = nullptr;
  DenoiserOptions options;
  std::string description;
  ~Impl() {
    if (device) oidnReleaseDevice(device);
  }
  // One RT filter run: `inputs` by name ("color", "albedo", "normal"),
  // written to `output` (which may be one of them).
  void run(const std::vector<std::pair<const char*, DeviceImage*>>& inputs, DeviceImage& output, int width,
           int height, bool hdr, bool clean_aux) const {
    OIDNFilter filter = oidnNewFilter(device, "RT");
    throw_if_failed(device, "creating the RT filter");
    for (const auto& [name, image] : inputs)
      oidnSetFilterImage(filter, name, image->buffer, OIDN_FORMAT_FLOAT3, size_t(width), size_t(height), 0, 0, 0);
    oidnSetFilterImage(filter, "output", output.buffer, OIDN_FORMAT_FLOAT3, size_t(width), size_t(height), 0, 0, 0);
    if (hdr) oidnSetFilterBool(filter, "hdr", true);
    if (clean_aux) oidnSetFilterBool(filter, "cleanAux", true);
    oidnSetFilterInt(filter, "quality", oidn_quality(options.quality));
    oidnCommitFilter(filter);
    const char* message = nullptr;
    OIDNError code = oidnGetDeviceError(device, &message);
    if (code == OIDN_ERROR_NONE) {
      oidnExecuteFilter(filter);
      code = oidnGetDeviceError(device, &message);
    }
    oidnReleaseFilter(filter);
    if (code != OIDN_ERROR_NONE)
      throw Error(std::string("Open Image Denoise: the RT filter failed: ") +
                  (message ? message : "error " + std::to_string(code)));
  }
};

Denoiser::Denoiser(const DenoiserOptions& options) : impl_(std::make_unique<Impl>()) {
  if (disabled_by_environment()) throw Error(missing_message() + " (CAUSTICA_NO_OIDN is set)");
  impl_->options = options;
  std::string cuda_note;
  if (options.gpu) {
    std::string why;
    impl_->device = new_device(OIDN_DEVICE_TYPE_CUDA, 0, &why);
    if (!impl_->device) cuda_note = "; OIDN's CUDA device is not available here (" + why + "), so the CPU denoises";
  }
  if (!impl_->device) {
    std::string why;
    impl_->device = new_device(OIDN_DEVICE_TYPE_CPU, options.threads, &why);
    if (!impl_->device) throw Error("Open Image Denoise: no CPU device: " + why);
  }
  // These declarations describe API version 2 (host/denoise/oidn_api.h).
  const int version = oidnGetDeviceInt(impl_->device, "version");
  if (version / 10000 != kOidnApiMajor)
    throw Error("Open Image Denoise " + std::to_string(version / 10000) + "." + std::to_string(version / 100 % 100) +
                " was found, but caustica calls the version " + std::to_string(kOidnApiMajor) +
                " API: install 2.x (tools/fetch_oidn.sh)");
  const int type = oidnGetDeviceInt(impl_->device, "type");
  const int threads = type == OIDN_DEVICE_TYPE_CPU ? oidnGetDeviceInt(impl_->device, "numThreads") : 0;
  impl_->description = "OIDN " + std::to_string(version / 10000) + "." + std::to_string(version / 100 % 100) + "." +
                       std::to_string(version % 100) + (type == OIDN_DEVICE_TYPE_CUDA ? " CUDA" : " CPU") +
                       (threads > 0 ? ", " + std::to_string(threads) + " threads" : std::string()) + ", quality " +
                       denoise_quality_name(options.quality) + cuda_note;
}

Denoiser::~Denoiser() = default;

const std::string& Denoiser::description() const { return impl_->description; }

ImageF Denoiser::denoise(const ImageF& colour, const DenoiseGuides& guides) const {
  if (colour.empty()) throw Error("denoise: an empty image");
  auto check = [&](const ImageF* guide, const char* what) {
    if (guide && (guide->width != colour.width || guide->height != colour.height))
      throw Error(std::string("denoise: the ") + what + " image is " + std::to_string(guide->width) + "x" +
                  std::to_string(guide->height) + ", the colour " + std::to_string(colour.width) + "x" +
                  std::to_string(colour.height));
  };
  check(guides.albedo, "albedo");
  check(guides.normal, "normal");
  if (guides.normal && !guides.albedo) throw Error("denoise: a normal guide needs an albedo guide too");
  const int w = colour.width, h = colour.height;
  const size_t pixels = colour.pixel_count();
  OIDNDevice device = impl_->device;
  DeviceImage in(device, pixels), out(device, pixels);
  in.write(colour);
  std::unique_ptr<DeviceImage> albedo, normal;
  std::vector<std::pair<const char*, DeviceImage*>> inputs{{"color", &in}};
  if (guides.albedo) {
    albedo = std::make_unique<DeviceImage>(device, pixels);
    albedo->write(*guides.albedo);
    // Noisy guides are denoised on their own first (in place), then given
    // to the colour filter as clean.
    if (!guides.clean && guides.prefilter) impl_->run({{"albedo", albedo.get()}}, *albedo, w, h, false, false);
    inputs.emplace_back("albedo", albedo.get());
  }
  if (guides.normal) {
    normal = std::make_unique<DeviceImage>(device, pixels);
    normal->write(*guides.normal);
    if (!guides.clean && guides.prefilter) impl_->run({{"normal", normal.get()}}, *normal, w, h, false, false);
    inputs.emplace_back("normal", normal.get());
  }
  // Guides that are clean, or were just cleaned: cleanAux (OIDN's best
  // quality; noisy guides given as clean would leave their noise in).
  impl_->run(inputs, out, w, h, true, guides.albedo != nullptr && (guides.clean || guides.prefilter));
  ImageF result(w, h);
  out.read(result);
  return result;
}

#endif

}  // namespace caustica
