// Preetham et al. 1999's sky and a sun disk (sky_model.h says what and why).
#include "host/scene/sky_model.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "host/math_constants.h"

namespace caustica {
namespace {

struct Perez {
  double a, b, c, d, e;
  // F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma)
  double f(double cos_theta, double gamma) const {
    const double cg = std::cos(gamma);
    return (1.0 + a * std::exp(b / std::max(cos_theta, 1e-3))) * (1.0 + c * std::exp(d * gamma) + e * cg * cg);
  }
};

// The paper's Perez coefficients for luminance Y and chromaticity x, y.
Perez perez_y(double t) { return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771, -0.0670 * t + 0.3703}; }
Perez perez_cx(double t) { return {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989, -0.0033 * t + 0.0452}; }
Perez perez_cy(double t) { return {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537, -0.0109 * t + 0.0529}; }

// Zenith values: luminance in kcd/m^2 and chromaticity (the paper's eq. A.2).
void zenith(double t, double theta_s, double* y, double* cx, double* cy) {
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * theta_s);
  *y = (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
  const double s = theta_s, s2 = s * s, s3 = s2 * s, t2 = t * t;
  *cx = t2 * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s) + t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s + 0.00394) +
        (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s + 0.25886);
  *cy = t2 * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s) + t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s + 0.00516) +
        (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s + 0.26688);
}

// CIE xyY to linear sRGB (D65 primaries).
void xyy_to_rgb(double cx, double cy, double y, float rgb[3]) {
  const double x = cy > 0.0 ? cx * y / cy : 0.0, z = cy > 0.0 ? (1.0 - cx - cy) * y / cy : 0.0;
  const double r = 3.2406 * x - 1.5372 * y - 0.4986 * z;
  const double g = -0.9689 * x + 1.8758 * y + 0.0415 * z;
  const double b = 0.0557 * x - 0.2040 * y + 1.0570 * z;
  rgb[0] = float(std::max(0.0, r));
  rgb[1] = float(std::max(0.0, g));
  rgb[2] = float(std::max(0.0, b));
}

// Map direction of (u, v) in the environment's convention.
void map_direction(double u, double v, double d[3]) {
  const double theta = kPi * v, phi = 2.0 * kPi * (u - 0.5);
  d[0] = std::sin(theta) * std::sin(phi);
  d[1] = std::cos(theta);
  d[2] = std::sin(theta) * std::cos(phi);
}

}  // namespace

void preetham_sun_radiance(const SkyParams& p, float rgb[3]) {
  const double elevation = p.sun_elevation;
  // Kasten and Young 1989: air mass of the zenith angle, finite at the horizon.
  const double air_mass = 1.0 / (std::sin(elevation * kPi / 180.0) + 0.50572 * std::pow(elevation + 6.07995, -1.6364));
  const double beta = 0.04608365822050 * p.turbidity - 0.04586025928522;
  const double lambda[3] = {0.680, 0.550, 0.450};  // micrometres
  const double rayleigh[3] = {0.044, 0.097, 0.22};
  const double extraterrestrial = 1.97e6;  // kcd/m^2
  for (int c = 0; c < 3; ++c) {
    const double depth = rayleigh[c] + std::max(0.0, beta) * std::pow(lambda[c], -1.3);
    rgb[c] = float(extraterrestrial * std::exp(-air_mass * depth) * kSkyRadianceScale);
  }
}

ImageF preetham_sky(const SkyParams& p) {
  ImageF img(p.width, p.height);
  const double t = p.turbidity, theta_s = (90.0 - p.sun_elevation) * kPi / 180.0;
  const double az = p.sun_azimuth * kPi / 180.0;
  const double sun[3] = {std::sin(theta_s) * std::sin(az), std::cos(theta_s), std::sin(theta_s) * std::cos(az)};
  const Perez fy = perez_y(t), fx = perez_cx(t), fc = perez_cy(t);
  double y_z, x_z, c_z;
  zenith(t, theta_s, &y_z, &x_z, &c_z);
  const double y0 = fy.f(1.0, theta_s), x0 = fx.f(1.0, theta_s), c0 = fc.f(1.0, theta_s);
  for (int row = 0; row < p.height; ++row)
    for (int col = 0; col < p.width; ++col) {
      double d[3];
      map_direction((col + 0.5) / p.width, (row + 0.5) / p.height, d);
      float* px = img.at(col, row);
      if (d[1] < 0.0) {  // below the horizon: the horizon's sky at that azimuth
        const double flat = std::hypot(d[0], d[2]);
        d[0] /= flat, d[1] = 0.0, d[2] /= flat;
      }
      const double gamma = std::acos(std::clamp(d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2], -1.0, 1.0));
      const double y = y_z * fy.f(d[1], gamma) / y0;
      const double cx = x_z * fx.f(d[1], gamma) / x0, cy = c_z * fc.f(d[1], gamma) / c0;
      xyy_to_rgb(cx, cy, y * kSkyRadianceScale, px);
    }
  // The sun: its radiance over its disk, spread over the texels it covers
  // (8 x 8 points a texel) and scaled so that the image holds exactly its
  // power, radiance x solid angle, however small it is against a texel.
  if (!p.sun_disk) return img;
  float sun_rgb[3];
  preetham_sun_radiance(p, sun_rgb);
  const double cos_sun = std::cos(kSunAngularRadiusDegrees * kPi / 180.0);
  const double sun_solid_angle = 2.0 * kPi * (1.0 - cos_sun);
  std::vector<std::pair<size_t, double>> covered;  // texel, solid angle inside the disk
  double covered_total = 0.0;
  const int sub = 8;
  const double margin = 2.0 * kSunAngularRadiusDegrees * kPi / 180.0 + 2.0 * kPi / p.height;
  for (int row = 0; row < p.height; ++row) {
    const double theta0 = kPi * row / p.height, theta1 = kPi * (row + 1) / p.height;
    if (theta1 < theta_s - margin || theta0 > theta_s + margin) continue;
    const double texel_solid_angle = 2.0 * kPi / p.width * (std::cos(theta0) - std::cos(theta1));
    for (int col = 0; col < p.width; ++col) {
      int inside = 0;
      for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) {
          double d[3];
          map_direction((col + (i + 0.5) / sub) / p.width, (row + (j + 0.5) / sub) / p.height, d);
          inside += d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2] >= cos_sun ? 1 : 0;
        }
      if (inside == 0) continue;
      const double share = texel_solid_angle * inside / (sub * sub);
      covered.emplace_back(size_t(row) * p.width + col, share);
      covered_total += share;
    }
  }
  if (covered.empty()) {  // narrower than one sub-point: the texel holding its centre
    const double u = 0.5 + std::atan2(sun[0], sun[2]) / (2.0 * kPi), v = std::acos(sun[1]) / kPi;
    const int col = std::min(p.width - 1, int(u * p.width)), row = std::min(p.height - 1, int(v * p.height));
    const double theta0 = kPi * row / p.height, theta1 = kPi * (row + 1) / p.height;
    covered.emplace_back(size_t(row) * p.width + col, 2.0 * kPi / p.width * (std::cos(theta0) - std::cos(theta1)));
    covered_total = covered.back().second;
  }
  for (const auto& [texel, share] : covered) {
    const int row = int(texel / p.width);
    const double theta0 = kPi * row / p.height, theta1 = kPi * (row + 1) / p.height;
    const double texel_solid_angle = 2.0 * kPi / p.width * (std::cos(theta0) - std::cos(theta1));
    // This texel's part of the sun's power, as radiance over the texel.
    const double scale = sun_solid_angle * (share / covered_total) / texel_solid_angle;
    for (int c = 0; c < 3; ++c) img.rgb[3 * texel + c] += float(sun_rgb[c] * scale);
  }
  return img;
}

}  // namespace caustica
