#include "host/scene/generate.h"

#include <cmath>

#include "host/error.h"

namespace caustica {

namespace {

using nlohmann::json;

// splitmix64: tiny, well mixed, and specified bit-for-bit, unlike the
// standard library's distributions.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  uint32_t below(uint32_t n) { return static_cast<uint32_t>(next() % n); }

 private:
  uint64_t state_;
};

struct V3 {
  double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Written values are rounded to 1e-4 (compact files) using only correctly
// rounded IEEE operations, so every platform prints the same digits.
double r4(double v) { return std::round(v * 10000.0) / 10000.0; }
json vec(V3 v) { return json::array({r4(v.x), r4(v.y), r4(v.z)}); }
json vec(double x, double y, double z) { return vec(V3{x, y, z}); }

// libm's cbrt/pow need not be correctly rounded; Newton's iteration with a
// fixed start and count is the same everywhere.
double cube_root(double a) {
  double x = 1.0;
  for (int i = 0; i < 100; ++i) x = (2.0 * x + a / (x * x)) / 3.0;
  return x;
}

V3 unit_vector(Rng& rng) {
  for (;;) {
    const V3 v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    const double l2 = dot(v, v);
    if (l2 > 1e-4 && l2 <= 1.0) return (1.0 / std::sqrt(l2)) * v;
  }
}

// The box the primitives are scattered in: in front of the camera, above the
// ground plane y = -0.5, filling most of the view.
constexpr V3 kBoxLo{-4.0, -0.5, -1.0};
constexpr V3 kBoxHi{4.0, 4.5, 5.0};
constexpr double kGroundY = -0.5;

// Sphere radius at 400 shapes, scaled by (400 / count)^(1/3). The optical
// depth through the box then still grows as count^(1/3); 0.12 keeps objects at
// about 20% of the image at 400 shapes and 35% at 12,800 (checked with a
// coarse ray cast), the rest being ground and background: never a solid wall.
constexpr double kBaseSize = 0.12;

const V3 kPalette[] = {{0.8, 0.3, 0.3}, {0.3, 0.7, 0.3}, {0.3, 0.4, 0.8}, {0.8, 0.7, 0.3},
                       {0.7, 0.3, 0.7}, {0.3, 0.7, 0.7}, {0.85, 0.85, 0.85}, {0.9, 0.5, 0.2}};
constexpr uint32_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

json material(V3 diffuse, double kd, double ks, double exponent, bool reflective, double reflectivity) {
  return json{{"ks", ks},
              {"kd", kd},
              {"specularexponent", exponent},
              {"diffusecolor", vec(diffuse)},
              {"specularcolor", vec(1, 1, 1)},
              {"isreflective", reflective},
              {"reflectivity", reflectivity},
              {"isrefractive", false},
              {"refractiveindex", 1.0}};
}

// A small set of materials, so the loader's deduplication keeps the material
// table tiny however many shapes there are; about 1 in 6 is a mirror.
json random_material(Rng& rng) {
  const V3 colour = kPalette[rng.below(kPaletteSize)];
  if (rng.below(6) == 0) return material(colour, 0.5, 0.4, 50, true, 0.6);
  return material(colour, 0.8, 0.2, 20, false, 1.0);
}

V3 random_point(Rng& rng, double margin) {
  return {rng.uniform(kBoxLo.x, kBoxHi.x), rng.uniform(kBoxLo.y + margin, kBoxHi.y),
          rng.uniform(kBoxLo.z, kBoxHi.z)};
}

json sphere(Rng& rng, double size) {
  const double radius = r4(size * rng.uniform(0.6, 1.4));
  // Braced lists evaluate left to right, so the draws happen in a fixed order.
  return json{{"type", "sphere"},
              {"center", vec(random_point(rng, radius))},
              {"radius", radius},
              {"material", random_material(rng)}};
}

json cylinder(Rng& rng, double size) {
  const double k = rng.uniform(0.6, 1.4);
  const double radius = r4(0.6 * size * k), half = r4(1.2 * size * k);
  return json{{"type", "cylinder"},
              {"center", vec(random_point(rng, half + radius))},
              {"axis", vec(unit_vector(rng))},
              {"radius", radius},
              {"height", half},
              {"material", random_material(rng)}};
}

// Three random points on a sphere of radius ~1.6 size; thin slivers are
// redrawn (an equilateral triangle has area 1.3 R^2).
json triangle(Rng& rng, double size) {
  const double radius = 1.6 * size * rng.uniform(0.6, 1.4);
  const V3 c = random_point(rng, radius);
  V3 a, b, d;
  do {
    a = unit_vector(rng);
    b = unit_vector(rng);
    d = unit_vector(rng);
  } while (0.5 * std::sqrt(dot(cross(b - a, d - a), cross(b - a, d - a))) < 0.4);
  return json{{"type", "triangle"},
              {"v0", vec(c + radius * a)},
              {"v1", vec(c + radius * b)},
              {"v2", vec(c + radius * d)},
              {"material", random_material(rng)}};
}

}  // namespace

std::string table1_scene_name(int shape_count, bool mixed) {
  return std::to_string(shape_count) + (mixed ? "_shapes" : "_spheres");
}

json generate_table1_scene(int shape_count, bool mixed, uint32_t seed) {
  if (shape_count < 1) throw Error("generate_table1_scene: shape_count must be at least 1, got " +
                                   std::to_string(shape_count));
  Rng rng((static_cast<uint64_t>(seed) << 32) ^ static_cast<uint64_t>(shape_count) * 2 ^ (mixed ? 1u : 0u));
  const double size = kBaseSize * cube_root(400.0 / shape_count);

  json shapes = json::array();
  // Ground: a sphere so that "spheres only" holds; radius 100 is flat enough
  // over the view and small enough for single-precision intersection.
  shapes.push_back(json{{"type", "sphere"},
                        {"center", vec(0, kGroundY - 100.0, 0)},
                        {"radius", 100.0},
                        {"material", material({0.6, 0.6, 0.6}, 0.9, 0.05, 10, false, 1.0)}});
  const int rest = shape_count - 1;
  const int thirds = mixed ? rest / 3 : 0;
  for (int i = 0; i < rest; ++i) {
    // Interleaved so that any prefix of the file is also mixed.
    const int kind = i < 3 * thirds ? i % 3 : 0;
    shapes.push_back(kind == 0 ? sphere(rng, size) : kind == 1 ? cylinder(rng, size) : triangle(rng, size));
  }

  json lights = json::array();
  lights.push_back(json{{"type", "pointlight"}, {"position", vec(-3, 6, -5)}, {"intensity", vec(0.6, 0.6, 0.6)}});
  lights.push_back(json{{"type", "pointlight"}, {"position", vec(4, 5, 1)}, {"intensity", vec(0.4, 0.4, 0.4)}});

  return json{
      {"_generator", "caustica generate_table1_scene(" + std::to_string(shape_count) + ", " +
                         (mixed ? "mixed" : "spheres") + ", seed " + std::to_string(seed) + ")"},
      {"nbounces", 8},
      {"rendermode", "phong"},
      {"camera",
       {{"type", "pinhole"},
        {"width", 1200},
        {"height", 800},
        {"position", vec(0, 2.5, -7.5)},
        {"lookAt", vec(0, 1.0, 1.5)},
        {"upVector", vec(0, 1, 0)},
        {"fov", 45.0},
        {"exposure", 0.0}}},
      {"scene", {{"backgroundcolor", vec(0.25, 0.25, 0.25)}, {"lightsources", lights}, {"shapes", shapes}}}};
}

}  // namespace caustica
