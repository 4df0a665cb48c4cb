#line 2 "kernels/shared/feature_flags.h"
/* The compile-time feature flags, declared once (issue 21).
 *
 * Rules: every flag is HAS_<FEATURE>, always has a value (0 or 1) and is
 * tested as `#if HAS_X`, never with #ifdef / defined(). A row is
 * X(macro, default, --verbose word, description); everything else reads this
 * table:
 *  - the host runtime completes every program's options with it
 *    (complete_feature_flags, host/cl/runtime.cpp): a flag the options do not
 *    name gets its default, and the flags are written in table order, so the
 *    program cache key depends on the flags' values only;
 *  - SceneFeatures::build_options and describe() (the --verbose line) are
 *    generated from it (host/scene/features.cpp);
 *  - the table in DESIGN.md ("Feature flags") lists the same rows, checked by
 *    tests/test_feature_flags.cpp, which also checks that kernels/ uses
 *    exactly these HAS_* names.
 * Defaults are what a program that does not name a flag has always had: the
 * scene-content flags, the photon pass and the numeric checks are 0 (a test
 * names what it needs), the two that only cut code out of the path tracer's
 * libraries are 1 (tests include those bare and get everything; the
 * clear coat is the third such).
 * Adding a flag is one row here, its #ifndef below, and its row in DESIGN.md;
 * SceneFeatures::flag_value must say how a scene sets it. */
#ifndef CAUSTICA_SHARED_FEATURE_FLAGS_H
#define CAUSTICA_SHARED_FEATURE_FLAGS_H

#define CS_FEATURE_FLAGS(X)                                                                                 \
  X(HAS_SPHERES, 0, "spheres", "sphere intersection and surface points")                                    \
  X(HAS_CYLINDERS, 0, "cylinders", "cylinder intersection and surface points")                              \
  X(HAS_TRIANGLES, 0, "triangles", "triangle intersection and surface points")                              \
  X(HAS_TRIANGLE_SHADING, 0, "vertex-data", "triangles' vertex normals and texture coordinates")            \
  X(HAS_TEXTURES, 0, "textures", "texture lookups, and texture coordinates on spheres and cylinders")       \
  X(HAS_LIGHTS, 0, "lights", "phong: point-light shading and its shadow rays")                              \
  X(HAS_REFLECTION, 0, "reflection", "phong: mirror rays are spawned")                                      \
  X(HAS_REFRACTION, 0, "refraction", "phong: refraction rays are spawned")                                  \
  X(HAS_DIELECTRIC, 1, "dielectric-bsdf", "the dielectric (glass) BSDF of the path tracer and photon pass") \
  X(HAS_AREA_LIGHTS, 1, "area-lights", "rectangle, sphere and emissive-shape lights are sampled")           \
  X(HAS_CAUSTICS, 0, "photon-pass", "the photon pass: photon stages, grid and caustic gathers")             \
  X(HAS_NUMERIC_CHECKS, 0, "numeric-checks", "path: the --check-numerics BSDF weight counters")               \
  X(HAS_ENVIRONMENT, 0, "environment", "the environment map: seen at misses, sampled, emitting photons")      \
  X(HAS_AUX_PASSES, 0, "aux-passes", "path: the albedo, normal and depth passes (denoiser, compositors)")          \
  X(HAS_LIGHT_TREE, 0, "light-tree", "path: next-event estimation picks lights through the light tree")         \
  X(HAS_NORMAL_MAPS, 0, "normal-maps", "triangles' tangents and their materials' normal maps")                    \
  X(HAS_VERTEX_COLOURS, 0, "vertex-colours", "triangles' vertex colours scale the base colour")                 \
  X(HAS_ALPHA_CUTOUTS, 0, "alpha-cutouts", "the traversal skips triangles' alpha-masked and blended texels")     \
  X(HAS_CLEARCOAT, 1, "clearcoat", "the clear coat over plastic and conductors (path tracer and photon pass)")

/* The defaults, for code that is not built by the runtime: the kernel library
 * compiled as C++ on the host (shared/compat.h includes this), or an OpenCL
 * build that bypasses complete_feature_flags. tests/test_feature_flags.cpp
 * static_asserts that these agree with the table. */
#ifndef HAS_SPHERES
#define HAS_SPHERES 0
#endif
#ifndef HAS_CYLINDERS
#define HAS_CYLINDERS 0
#endif
#ifndef HAS_TRIANGLES
#define HAS_TRIANGLES 0
#endif
#ifndef HAS_TRIANGLE_SHADING
#define HAS_TRIANGLE_SHADING 0
#endif
#ifndef HAS_TEXTURES
#define HAS_TEXTURES 0
#endif
#ifndef HAS_LIGHTS
#define HAS_LIGHTS 0
#endif
#ifndef HAS_REFLECTION
#define HAS_REFLECTION 0
#endif
#ifndef HAS_REFRACTION
#define HAS_REFRACTION 0
#endif
#ifndef HAS_DIELECTRIC
#define HAS_DIELECTRIC 1
#endif
#ifndef HAS_AREA_LIGHTS
#define HAS_AREA_LIGHTS 1
#endif
#ifndef HAS_CAUSTICS
#define HAS_CAUSTICS 0
#endif
#ifndef HAS_NUMERIC_CHECKS
#define HAS_NUMERIC_CHECKS 0
#endif

#ifndef HAS_ENVIRONMENT
#define HAS_ENVIRONMENT 0
#endif
#ifndef HAS_LIGHT_TREE
#define HAS_LIGHT_TREE 0
#endif
#ifndef HAS_AUX_PASSES
#define HAS_AUX_PASSES 0
#endif
#ifndef HAS_NORMAL_MAPS
#define HAS_NORMAL_MAPS 0
#endif
#ifndef HAS_VERTEX_COLOURS
#define HAS_VERTEX_COLOURS 0
#endif
#ifndef HAS_ALPHA_CUTOUTS
#define HAS_ALPHA_CUTOUTS 0
#endif
#ifndef HAS_CLEARCOAT
#define HAS_CLEARCOAT 1
#endif

#ifndef __OPENCL_C_VERSION__
/* The host's view of the table. Names are stringised (#name): the macro
 * itself expands to its value here. */
namespace caustica {
struct FeatureFlagInfo {
  const char* name;
  int default_value;
  const char* word;  // in the --verbose feature line
  const char* description;
};
#define CS_FEATURE_FLAG_INFO(name, def, word, description) {#name, def, word, description},
inline constexpr FeatureFlagInfo kFeatureFlags[] = {CS_FEATURE_FLAGS(CS_FEATURE_FLAG_INFO)};
#undef CS_FEATURE_FLAG_INFO
/* FeatureFlag::kHAS_X indexes kFeatureFlags (the enumerators are pasted, so
 * the macros do not expand in them). */
#define CS_FEATURE_FLAG_ENUM(name, def, word, description) k##name,
enum class FeatureFlag { CS_FEATURE_FLAGS(CS_FEATURE_FLAG_ENUM) };
#undef CS_FEATURE_FLAG_ENUM
inline constexpr int kFeatureFlagCount = int(sizeof kFeatureFlags / sizeof kFeatureFlags[0]);
}  // namespace caustica
#endif

#endif /* CAUSTICA_SHARED_FEATURE_FLAGS_H */
