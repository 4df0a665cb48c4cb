// Display transform from linear HDR radiance to 8-bit output. Per channel:
//   x = hdr * exposure_scale
//   x = curve(x)            Linear: x; Reinhard: x/(1+x); Aces: Narkowicz fit
//   x = clamp(x, 0, 1)
//   x = x^(1/gamma)
//   byte = floor(x*255 + 0.5)
// Non-finite input never reaches a float->int conversion: NaN -> 0, +Inf -> 1
// (full white), -Inf -> 0, so a stray bad sample shows as a dot, not as UB.
#pragma once

#include <cstdint>
#include <string>

#include "host/image/image.h"

namespace caustica {

enum class ToneMap { Linear, Reinhard, Aces };

// "linear", "reinhard", "aces" (case-insensitive); throws Error listing them.
ToneMap parse_tonemap(const std::string& name);
const char* tonemap_name(ToneMap tm);

struct DisplaySettings {
  ToneMap tonemap = ToneMap::Linear;
  float exposure_scale = 1.0f;
  float gamma = 1.0f;
};

// Throws Error unless gamma is finite and > 0 and exposure_scale is finite
// and >= 0: caught here so a bad CLI value is reported, not rendered black.
void validate(const DisplaySettings& display);

// The bare curve, without exposure, clamp or gamma (for tests and kernels
// that must match the host).
float tonemap_curve(ToneMap tm, float x);

// The whole per-channel transform, result in [0, 1] before quantisation.
float display_value(float hdr, const DisplaySettings& display);
uint8_t display_byte(float hdr, const DisplaySettings& display);

Image8 to_display(const ImageF& hdr, const DisplaySettings& display);

}  // namespace caustica
