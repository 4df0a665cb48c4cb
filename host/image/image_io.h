// Image files. Writers pick the format from the extension (case-insensitive):
//   .ppm  ASCII P3, maxval 255, one "r g b" pixel per line (tone mapped)
//   .png  8-bit RGB via stb_image_write (tone mapped)
//   .pfm  little-endian float RGB, scale -1.0, rows bottom-to-top (HDR)
//   .exr  32-bit float RGB via tinyexr (HDR)
//   .exr  with write_exr_with_spp: also a FLOAT channel "spp", the per-pixel
//         sample count of an adaptive render
// HDR formats store hdr * exposure_scale with no curve, clamp or gamma, so a
// reference written at one exposure can be compared in linear units.
// Every failure throws caustica::Error naming the file; a write succeeds only
// when every byte reached the file and it was closed without error. Reads
// are bounded (host/read_file.h) and every declared size is checked against
// host/limits.h before pixels are allocated.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/image/image.h"
#include "host/image/tonemap.h"

namespace caustica {

void write_image(const std::string& path, const ImageF& hdr, const DisplaySettings& display);
void write_image8(const std::string& path, const Image8& img);  // .ppm or .png only

// The .exr that write_image writes (R, G, B = hdr * exposure_scale) plus a
// FLOAT channel "spp": spp[i] samples at pixel i, row-major, top row first.
// Throws naming the file unless spp holds one count per pixel.
void write_exr_with_spp(const std::string& path, const ImageF& hdr, float exposure_scale,
                        const std::vector<uint32_t>& spp);

// One float plane of an EXR file: pixel_count values, top row first, named
// as OpenEXR layers are ("R", "albedo.R", "depth.Z", "spp").
struct ExrPlane {
  std::string name;
  std::vector<float> values;
};
// Writes the planes (sorted by name, as OpenEXR wants) as 32-bit float
// channels of a ZIP-compressed scanline EXR; throws naming the file on a
// failed write.
void write_exr_planes(const std::string& path, int width, int height, std::vector<ExrPlane> planes);
// The channel names of a single-part scanline EXR, in file order.
std::vector<std::string> read_exr_channel_names(const std::string& path);

// One channel of a single-part scanline EXR as floats, row-major, top row
// first (HALF and UINT channels converted). Throws naming the file and the
// channel when the file has no channel of that name.
std::vector<float> read_exr_channel(const std::string& path, const std::string& channel);
// The same, with the image's size.
std::vector<float> read_exr_channel(const std::string& path, const std::string& channel, int* width, int* height);

// Throws unless `path` can be written by write_image as far as can be told
// without creating it: a supported extension and an existing directory.
// Commands call it before any work, so a typo does not cost a render.
void check_output_image_path(const std::string& path);

// The extension in lower case, with its dot (".exr"); "" without one.
std::string lower_extension(const std::string& path);
// Does the extension name an HDR format (.pfm/.exr)?
bool is_hdr_path(const std::string& path);

// 8-bit RGB from PNG/JPEG/BMP/TGA/binary PNM (stb_image, forced to 3 channels)
// and ASCII P3 PPM (which stb does not read; our own .ppm output is P3).
Image8 read_image8(const std::string& path);

ImageF read_pfm(const std::string& path);
ImageF read_exr(const std::string& path);
// .pfm or .exr by extension.
ImageF read_hdr_image(const std::string& path);

}  // namespace caustica
