// The environment light (environment_light.h says what and its rules).
#include "host/lights/environment_light.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/error.h"
#include "host/image/image_io.h"
#include "host/lights/light_types.h"
#include "host/limits.h"
#include "host/math_constants.h"
#include "host/read_file.h"
#include "host/scene/scene_reader.h"
#include "host/scene/sky_model.h"
#include "host/scene/textures.h"

namespace caustica {
namespace {

using namespace scene_detail;

double texel_luminance(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// The file's linear texels: HDR formats as stored, 8-bit ones sRGB-decoded.
LinearImage read_map(const std::string& path) {
  LinearImage out;
  const std::string ext = lower_extension(path);
  if (ext == ".pfm" || ext == ".exr") {
    const ImageF img = read_hdr_image(path);  // throws, naming the file
    out.width = img.width, out.height = img.height;
    out.rgb = img.rgb;
    return out;
  }
  const std::string data = read_input_file(path, "environment map", limits::kMaxImageFileBytes);
  if (std::string why = decode_texture_image(data, out); !why.empty()) throw Error(path + ": " + why);
  return out;
}

SkyParams read_sky(const Reader& r, const json& sky, const std::string& path) {
  r.object(sky, path);
  r.check_keys(sky, path, {"sun_elevation", "sun_azimuth", "turbidity", "resolution"});
  SkyParams p;
  p.sun_elevation = r.read_number(sky, "sun_elevation", path, Range::Any, p.sun_elevation);
  if (!(p.sun_elevation >= 0.5f && p.sun_elevation <= 90.0f))
    r.expected(path + "/sun_elevation", "degrees above the horizon from 0.5 to 90", sky["sun_elevation"]);
  p.sun_azimuth = r.read_number(sky, "sun_azimuth", path, Range::Any, p.sun_azimuth);
  p.turbidity = r.read_number(sky, "turbidity", path, Range::Any, p.turbidity);
  if (!(p.turbidity >= 1.7f && p.turbidity <= 10.0f))
    r.expected(path + "/turbidity", "a turbidity from 1.7 to 10 (Preetham's fitted range)", sky["turbidity"]);
  if (const json* res = Reader::find(sky, "resolution")) {
    const glm::vec2 wh = r.vec2(*res, path + "/resolution", Range::Positive);
    // At most 8 Mi texels: the image, its distribution and the device's
    // copy stay within a few hundred MiB (a scene file cannot ask for more).
    if (!(wh.x >= 8 && wh.y >= 4 && wh.x <= 4096 && wh.y <= 2048 && wh.x == std::floor(wh.x) && wh.y == std::floor(wh.y)))
      r.expected(path + "/resolution", "[width, height], whole numbers from [8, 4] to [4096, 2048]", *res);
    p.width = int(wh.x), p.height = int(wh.y);
  }
  return p;
}

float environment_power(const Light& l) {
  return float(kPi * double(l.p0.w) * double(l.p0.w) * double(l.p1.x));
}

}  // namespace

Scene::Environment make_environment(const std::string& source, int width, int height, std::vector<float> rgb,
                                    float intensity, const glm::mat3& rotation) {
  if (width < 1 || height < 1 || width > limits::kMaxTextureSide || height > limits::kMaxTextureSide ||
      uint64_t(width) * uint64_t(height) > limits::kMaxTexturePixels)
    throw Error(source + ": expected an environment map of at most " + std::to_string(limits::kMaxTextureSide) +
                " texels a side and " + std::to_string(limits::kMaxTexturePixels) + " in all, got " +
                std::to_string(width) + "x" + std::to_string(height));
  if (rgb.size() != size_t(width) * size_t(height) * 3) throw Error(source + ": internal: texel count mismatch");
  for (size_t i = 0; i < rgb.size(); ++i) {
    if (!(std::isfinite(rgb[i]) && rgb[i] >= 0.0f)) {
      const size_t t = i / 3;
      throw Error(source + ": texel (" + std::to_string(t % width) + ", " + std::to_string(t / width) +
                  "): expected finite non-negative radiance, got " + std::to_string(rgb[i]));
    }
    rgb[i] *= intensity;
    if (!std::isfinite(rgb[i]))
      throw Error(source + ": texel (" + std::to_string(i / 3 % size_t(width)) + ", " +
                  std::to_string(i / 3 / size_t(width)) + ") times the intensity (/scene/environment/intensity " +
                  [&] {
                    char t[32];
                    std::snprintf(t, sizeof t, "%g", double(intensity));
                    return std::string(t);
                  }() + ") is not finite in single precision");
  }
  Scene::Environment env;
  env.source = source;
  env.width = width, env.height = height;
  env.rgb = std::move(rgb);
  env.rotation = rotation;
  return env;
}

void read_environment(LoadContext& ctx, const json& scene_obj) {
  const json* e = Reader::find(scene_obj, "environment");
  if (!e) return;
  const Reader& r = ctx.r;
  const std::string path = "/scene/environment";
  r.object(*e, path);
  r.check_keys(*e, path, {"file", "sky", "intensity", "rotate", "importance"});
  const bool importance = r.read_bool(*e, "importance", path, true);
  if (Reader::find(scene_obj, "backgroundcolor"))
    r.fail("/scene", "expected either \"backgroundcolor\" (a constant sky) or \"environment\", got both");
  const float intensity = r.read_number(*e, "intensity", path, Range::NonNegative, 1.0f);
  const glm::mat3 rotation = rotation_xyz(r.read_vec3(*e, "rotate", path, Range::Any, glm::vec3(0.0f)));
  const json* file = Reader::find(*e, "file");
  const json* sky = Reader::find(*e, "sky");
  if ((file != nullptr) == (sky != nullptr))
    r.fail(path, "expected exactly one of \"file\" (an equirectangular image) and \"sky\" (the sun-and-sky model)");
  if (sky) {
    const SkyParams p = read_sky(r, *sky, path + "/sky");
    ImageF img = preetham_sky(p);
    const std::string source = r.file() + ": " + path + "/sky";
    ctx.scene.environment = make_environment(source, img.width, img.height, std::move(img.rgb), intensity, rotation);
    ctx.scene.environment->importance = importance;
    return;
  }
  const std::string written = r.string(*file, path + "/file");
  std::string tried;
  const std::string resolved = ctx.assets.find(written, "textures", &tried);
  if (resolved.empty())
    r.fail(path + "/file", "expected an existing environment map (.hdr, .exr, .pfm or an 8-bit image), got \"" +
                               written + "\" (looked " + tried + ")");
  LinearImage img;
  try {
    img = read_map(resolved);
  } catch (const Error& err) {
    r.fail(path + "/file", std::string("could not read the environment map: ") + err.what());
  }
  try {
    ctx.scene.environment = make_environment(resolved, img.width, img.height, std::move(img.rgb), intensity, rotation);
  } catch (const Error& err) {
    r.fail(path + "/file", err.what());
  }
  ctx.scene.environment->importance = importance;
}

double environment_luminance_integral(const Scene::Environment& env) {
  double total = 0.0;
  for (int y = 0; y < env.height; ++y) {
    const double solid = 2.0 * kPi / env.width *
                         (std::cos(kPi * y / env.height) - std::cos(kPi * (y + 1) / env.height));
    double row = 0.0;
    for (int x = 0; x < env.width; ++x) row += texel_luminance(&env.rgb[3 * (size_t(y) * env.width + x)]);
    total += row * solid;
  }
  return total;
}

std::vector<float> environment_device_data(const Scene::Environment& env) {
  const size_t w = size_t(env.width), h = size_t(env.height);
  std::vector<float> data(ENV_HEADER_FLOATS + 4 * w * h + (h + 1) + h * (w + 1), 0.0f);
  // f = luminance x sin(row centre); CDFs in double, normalised to end at 1.
  std::vector<double> row_sum(h, 0.0);
  float* cond = data.data() + ENV_HEADER_FLOATS + 4 * w * h + (h + 1);
  std::vector<double> f(w);
  for (size_t y = 0; y < h; ++y) {
    const double sin_row = std::sin(kPi * (double(y) + 0.5) / double(h));
    double sum = 0.0;
    for (size_t x = 0; x < w; ++x) {
      const float* c = &env.rgb[3 * (y * w + x)];
      for (int k = 0; k < 3; ++k) data[ENV_HEADER_FLOATS + 4 * (y * w + x) + k] = c[k];
      f[x] = (env.importance ? texel_luminance(c) : 1.0) * sin_row;
      sum += f[x];
    }
    row_sum[y] = sum;
    float* c = cond + y * (w + 1);
    double prefix = 0.0;
    for (size_t x = 0; x < w; ++x) {
      c[x] = float(sum > 0.0 ? prefix / sum : double(x) / double(w));
      prefix += f[x];
    }
    c[w] = 1.0f;
  }
  double total = 0.0;
  for (double s : row_sum) total += s;
  float* marginal = data.data() + ENV_HEADER_FLOATS + 4 * w * h;
  double prefix = 0.0;
  for (size_t y = 0; y < h; ++y) {
    marginal[y] = float(total > 0.0 ? prefix / total : double(y) / double(h));
    prefix += row_sum[y];
  }
  marginal[h] = 1.0f;
  data[0] = float(w);
  data[1] = float(h);
  data[2] = total > 0.0 ? float(double(w) * double(h) / total) : 0.0f;
  data[3] = env.importance ? 1.0f : 0.0f;
  // World -> map: the rows of M = R^T are the columns of R (glm: R[c]).
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 3; ++k) data[4 + 4 * row + k] = env.rotation[row][k];
  return data;
}

std::vector<float> environment_device_data(const Scene& scene) {
  return scene.environment ? environment_device_data(*scene.environment) : std::vector<float>{};
}

Light environment_light(const Scene& scene) {
  Light l{};
  l.kind = LIGHT_ENVIRONMENT;
  l.p0 = scene_bounding_sphere(scene);
  const Scene::Environment& env = *scene.environment;
  l.p1 = cs_float4{float(environment_luminance_integral(env)), 0.0f, 0.0f, 0.0f};
  glm::vec3 most(0.0f);
  for (size_t i = 0; i < env.rgb.size(); i += 3) most = glm::max(most, glm::vec3(env.rgb[i], env.rgb[i + 1], env.rgb[i + 2]));
  l.emitted = to_float4(most, 0.0f);
  return l;
}

LightType environment_light_type() {
  LightType t;
  t.kind = LIGHT_ENVIRONMENT;
  t.power = environment_power;
  return t;
}

}  // namespace caustica
