// An analytic sun and sky written to an equirectangular image (the
// environment's "sky" form, scenes/FORMAT.md; docs/environment.md).
//
// Rules: the sky is Preetham, Shirley and Smits 1999 ("A practical
// analytic model for daylight"): the Perez luminance distribution with its
// five coefficients linear in turbidity, per channel of CIE xyY, and the
// zenith luminance and chromaticity fitted to the sun's zenith angle and
// turbidity; converted to linear sRGB. Hosek and Wilkie 2012 fits sky
// radiance better near the horizon at high turbidity, but it is a table of
// about 11,000 fitted coefficients that no Debian package ships; Preetham
// is closed-form, so it is written here from the paper. The sun is a disk
// of 0.533 degrees whose luminance is the extraterrestrial sun's (1.6e9 *
// 1.23 cd/m^2 ~ 1.97e9) attenuated along the Kasten-Young air mass by
// Rayleigh optical depths per channel (0.044, 0.097, 0.22 at 680, 550 and
// 450 nm) and Preetham's Angstrom aerosol depth beta lambda^-1.3 with
// beta = 0.04608 T - 0.04586 (the paper's appendix): a broadband stand-in for
// the paper's spectral sun, correct in magnitude and reddening. Below the
// horizon each column repeats the sky at the horizon (Preetham is not
// defined there; a finite ground then meets a sky of its own colour rather
// than a black band). Units: the
// image holds luminance in kcd/m^2 times kSkyRadianceScale, so that a white
// ground lit by a high sun is near 1.
#pragma once

#include "host/image/image.h"

namespace caustica {

struct SkyParams {
  float sun_elevation = 45.0f;  // degrees above the horizon, 0.5 to 90
  float sun_azimuth = 0.0f;     // degrees from the map's +z toward +x
  float turbidity = 3.0f;       // 1.7 (very clear) to 10 (hazy)
  int width = 1024, height = 512;
  bool sun_disk = true;  // false: the sky alone (tests measure the disk against it)
};

inline constexpr float kSkyRadianceScale = 0.05f;  // image value per kcd/m^2
inline constexpr float kSunAngularRadiusDegrees = 0.2665f;

// The sky in map space (the environment's convention: +y up, the image's
// centre along +z); row-major from the top row, linear rgb.
ImageF preetham_sky(const SkyParams& p);

// The sun's radiance (linear rgb, same units) for a sun at that elevation.
void preetham_sun_radiance(const SkyParams& p, float rgb[3]);

}  // namespace caustica
