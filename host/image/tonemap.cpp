#include "host/image/tonemap.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace caustica {

ToneMap parse_tonemap(const std::string& name) {
  std::string lower = name;
  for (auto& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "linear") return ToneMap::Linear;
  if (lower == "reinhard") return ToneMap::Reinhard;
  if (lower == "aces") return ToneMap::Aces;
  throw Error("unknown tone map '" + name + "' (expected one of: linear, reinhard, aces)");
}

const char* tonemap_name(ToneMap tm) {
  switch (tm) {
    case ToneMap::Linear: return "linear";
    case ToneMap::Reinhard: return "reinhard";
    case ToneMap::Aces: return "aces";
  }
  return "linear";
}

void validate(const DisplaySettings& display) {
  if (!std::isfinite(display.gamma) || display.gamma <= 0.0f)
    throw Error("display gamma must be a finite number > 0, got " + std::to_string(display.gamma));
  if (!std::isfinite(display.exposure_scale) || display.exposure_scale < 0.0f)
    throw Error("exposure scale must be a finite number >= 0, got " +
                std::to_string(display.exposure_scale));
}

float tonemap_curve(ToneMap tm, float x) {
  switch (tm) {
    case ToneMap::Linear: return x;
    case ToneMap::Reinhard: return x / (1.0f + x);
    case ToneMap::Aces: return x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
  }
  return x;
}

float display_value(float hdr, const DisplaySettings& display) {
  float x = hdr * display.exposure_scale;
  if (std::isnan(x)) return 0.0f;
  // Every curve is >= its value at 1e8 beyond this point and maps it to 1 after
  // the clamp; capping first keeps Reinhard's Inf/Inf and ACES's overflowing
  // x*x from producing NaN. Negative radiance is not displayable: black, and it
  // also keeps Reinhard away from its pole at -1.
  x = std::clamp(x, 0.0f, 1e8f);
  float y = std::clamp(tonemap_curve(display.tonemap, x), 0.0f, 1.0f);
  if (display.gamma != 1.0f) y = std::pow(y, 1.0f / display.gamma);
  // A non-positive or NaN gamma would make pow return NaN/Inf; never let that
  // reach the byte conversion.
  if (!(y >= 0.0f)) return 0.0f;
  return std::min(y, 1.0f);
}

uint8_t display_byte(float hdr, const DisplaySettings& display) {
  return static_cast<uint8_t>(display_value(hdr, display) * 255.0f + 0.5f);
}

Image8 to_display(const ImageF& hdr, const DisplaySettings& display) {
  validate(display);
  if (hdr.rgb.size() != hdr.pixel_count() * 3)
    throw Error("to_display: image says " + std::to_string(hdr.width) + "x" + std::to_string(hdr.height) +
                " but holds " + std::to_string(hdr.rgb.size()) + " floats");
  Image8 out(hdr.width, hdr.height);
  for (size_t i = 0; i < hdr.rgb.size(); ++i) out.rgb[i] = display_byte(hdr.rgb[i], display);
  return out;
}

}  // namespace caustica
