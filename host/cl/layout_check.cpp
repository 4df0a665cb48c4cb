// The device layout of kernels/shared/types.h (and photon.h, records.h) must be the same in C++ and
// OpenCL C: fixed sizes, 16-byte float4 alignment, explicit padding. These
// asserts catch a field added on one side only, or a padding slip.
#include <cstddef>

#include "kernels/shared/photon.h"
#include "kernels/shared/records.h"
#include "kernels/shared/types.h"

static_assert(sizeof(cs_float4) == 16 && alignof(cs_float4) == 16, "float4 layout");
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, material) == 16, "Sphere layout");
static_assert(sizeof(Cylinder) == 48 && offsetof(Cylinder, axis_half) == 16 && offsetof(Cylinder, material) == 32,
              "Cylinder layout");
static_assert(sizeof(Triangle) == 64 && offsetof(Triangle, v1) == 16 && offsetof(Triangle, v2) == 32 &&
                  offsetof(Triangle, material) == 48,
              "Triangle layout");
static_assert(sizeof(TriangleShading) == 80 && offsetof(TriangleShading, n2) == 32 &&
                  offsetof(TriangleShading, u0) == 48 && offsetof(TriangleShading, u2) == 64,
              "TriangleShading layout");
static_assert(sizeof(TriangleTangents) == 48 && offsetof(TriangleTangents, t2) == 32, "TriangleTangents layout");
static_assert(sizeof(TriangleColours) == 24, "TriangleColours layout");
static_assert(sizeof(TriangleAlpha) == 64 && offsetof(TriangleAlpha, mode) == 32 && offsetof(TriangleAlpha, sampling) == 48,
              "TriangleAlpha layout");
static_assert(sizeof(Texture) == 96 && offsetof(Texture, kind) == 64 && offsetof(Texture, scale) == 80 &&
                  offsetof(Texture, sampling) == 84,
              "Texture layout");
static_assert(sizeof(BvhNode8) == 256 && offsetof(BvhNode8, hi_x) == 32 && offsetof(BvhNode8, lo_y) == 64 &&
                  offsetof(BvhNode8, hi_z) == 160 && offsetof(BvhNode8, child) == 192 &&
                  offsetof(BvhNode8, height) == 224,
              "BvhNode8 layout");
static_assert(sizeof(TriangleBlock4) == 160 && offsetof(TriangleBlock4, ref) == 144, "TriangleBlock4 layout");
static_assert(sizeof(Material) == 144 && offsetof(Material, clearcoat_roughness_texture) == 132 && offsetof(Material, alpha_cutoff) == 100 && offsetof(Material, volume) == 112 && offsetof(Material, specular) == 16 && offsetof(Material, emission) == 32 &&
                  offsetof(Material, specular_exponent) == 48 && offsetof(Material, ka) == 60 &&
                  offsetof(Material, flags) == 64 && offsetof(Material, texture) == 68 &&
                  offsetof(Material, roughness) == 72 && offsetof(Material, metallic) == 76 &&
                  offsetof(Material, roughness_texture) == 80 && offsetof(Material, emission_texture) == 84 &&
                  offsetof(Material, normal_texture) == 88 && offsetof(Material, normal_scale) == 92,
              "Material layout");
static_assert(sizeof(Light) == 80 && offsetof(Light, emitted) == 48 && offsetof(Light, kind) == 64 &&
                  offsetof(Light, select_cdf) == 72,
              "Light layout");
static_assert(sizeof(CameraGPU) == 96 && offsetof(CameraGPU, lens) == 64 && offsetof(CameraGPU, width) == 80 &&
                  offsetof(CameraGPU, pixel_count) == 92,
              "CameraGPU layout");
static_assert(sizeof(ShadeParams) == 64 && offsetof(ShadeParams, ambient_light) == 16 &&
                  offsetof(ShadeParams, light_count) == 32 && offsetof(ShadeParams, min_weight) == 44,
              "ShadeParams layout");
static_assert(sizeof(PathParams) == 64 && offsetof(PathParams, light_count) == 16 &&
                  offsetof(PathParams, rr_depth) == 40 && offsetof(PathParams, wave_samples) == 52 &&
                  offsetof(PathParams, environment_light) == 60,
              "PathParams layout");
static_assert(sizeof(Hit) == 16 && offsetof(Hit, prim) == 12, "Hit layout");
static_assert(sizeof(FilmAccumulate) == 32 && offsetof(FilmAccumulate, pass_count) == 12 &&
                  offsetof(FilmAccumulate, per_pixel) == 16 && offsetof(FilmAccumulate, colour_values) == 20,
              "FilmAccumulate layout");
static_assert(sizeof(PathRecord) == 80 && offsetof(PathRecord, throughput) == 32 && offsetof(PathRecord, pixel) == 48 &&
                  offsetof(PathRecord, depth) == 52 && offsetof(PathRecord, bsdf_pdf) == 56 &&
                  offsetof(PathRecord, flags) == 60 && offsetof(PathRecord, sample) == 64 &&
                  offsetof(PathRecord, cone_width) == 68 && offsetof(PathRecord, cone_spread) == 72 &&
                  offsetof(PathRecord, light_normal) == 76,
              "PathRecord layout");
static_assert(sizeof(PhotonRecord) == 64 && offsetof(PhotonRecord, power) == 32 && offsetof(PhotonRecord, index) == 48 &&
                  offsetof(PhotonRecord, depth) == 52 && offsetof(PhotonRecord, path_length) == 56 &&
                  offsetof(PhotonRecord, flags) == 60,
              "PhotonRecord layout");
static_assert(sizeof(ShadowRecord) == 64 && offsetof(ShadowRecord, contribution) == 32 &&
                  offsetof(ShadowRecord, pixel) == 48 && offsetof(ShadowRecord, tmax) == 52,
              "ShadowRecord layout");

// One flag namespace per record: every flag a single bit, no two of one
// record sharing it (their sum is then their union).
#define FLAG_SUM(name, bit) +(0u + (name))
#define FLAG_UNION(name, bit) | (0u + (name))
#define FLAG_SINGLE_BIT(name, bit) &&(0u + (name)) == (1u << (bit))
static_assert((0u PATH_FLAGS(FLAG_SUM)) == (0u PATH_FLAGS(FLAG_UNION)) && (true PATH_FLAGS(FLAG_SINGLE_BIT)),
              "PATH_FLAGS share a bit");
static_assert((0u PHOTON_FLAGS(FLAG_SUM)) == (0u PHOTON_FLAGS(FLAG_UNION)) && (true PHOTON_FLAGS(FLAG_SINGLE_BIT)),
              "PHOTON_FLAGS share a bit");
#undef FLAG_SUM
#undef FLAG_UNION
#undef FLAG_SINGLE_BIT

static_assert(sizeof(cs_packed3) == 12 && alignof(cs_packed3) == 4, "cs_packed3 layout");
static_assert(sizeof(Photon) == 48 && offsetof(Photon, bounces) == 12 && offsetof(Photon, wi) == 16 &&
                  offsetof(Photon, phong_scale) == 28 && offsetof(Photon, power) == 32,
              "Photon layout");
static_assert(sizeof(PhotonGridParams) == 32 && offsetof(PhotonGridParams, cell_size) == 16 &&
                  offsetof(PhotonGridParams, inv_cell_size) == 20 && offsetof(PhotonGridParams, table_size) == 24 &&
                  offsetof(PhotonGridParams, photon_count) == 28,
              "PhotonGridParams layout");
static_assert(sizeof(PhotonPassParams) == 64 && offsetof(PhotonPassParams, alpha) == 24 &&
                  offsetof(PhotonPassParams, radius_cap) == 28 && offsetof(PhotonPassParams, footprint_radius) == 32 &&
                  offsetof(PhotonPassParams, first_photon) == 36 && offsetof(PhotonPassParams, pixel_end) == 48,
              "PhotonPassParams layout");
static_assert(sizeof(VisiblePoint) == 96 && offsetof(VisiblePoint, recorded) == 12 &&
                  offsetof(VisiblePoint, normal) == 16 && offsetof(VisiblePoint, depth) == 28 &&
                  offsetof(VisiblePoint, wo) == 32 && offsetof(VisiblePoint, footprint) == 44 &&
                  offsetof(VisiblePoint, beta) == 48 && offsetof(VisiblePoint, kind) == 60 &&
                  offsetof(VisiblePoint, diffuse) == 64 && offsetof(VisiblePoint, alpha) == 76 &&
                  offsetof(VisiblePoint, specular) == 80 && offsetof(VisiblePoint, ior) == 92,
              "VisiblePoint layout");
static_assert(sizeof(SppmPixel) == 64 && offsetof(SppmPixel, photons) == 48 && offsetof(SppmPixel, radius2) == 52 &&
                  offsetof(SppmPixel, footprint2) == 56 && offsetof(SppmPixel, sum_r2) == 60,
              "SppmPixel layout");
