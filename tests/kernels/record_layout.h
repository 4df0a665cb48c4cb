#line 2 "tests/kernels/record_layout.h"
/* Every size and offset of the shared structs and records that the host
 * and the device must agree on, as one X-macro list: RecordLayout
 * (tests/test_render_core.cpp) evaluates it with the host's compiler and,
 * through tests/kernels/record_layout.cl, with the device's. Only a macro:
 * the includer brings kernels/shared/records.h and photon.h first. */
#ifndef CAUSTICA_TESTS_RECORD_LAYOUT_H
#define CAUSTICA_TESTS_RECORD_LAYOUT_H

#define LAYOUT_EXPRESSIONS(X)                                                                              \
  X(sizeof(Hit)) X(__builtin_offsetof(Hit, u)) X(__builtin_offsetof(Hit, prim))                            \
  X(sizeof(PathRecord)) X(__builtin_offsetof(PathRecord, dir)) X(__builtin_offsetof(PathRecord, throughput)) \
  X(__builtin_offsetof(PathRecord, pixel)) X(__builtin_offsetof(PathRecord, depth))                        \
  X(__builtin_offsetof(PathRecord, bsdf_pdf)) X(__builtin_offsetof(PathRecord, sample))                     \
  X(sizeof(Light)) X(__builtin_offsetof(Light, emitted)) X(__builtin_offsetof(Light, select_cdf)) \
  X(sizeof(ShadowRecord)) X(__builtin_offsetof(ShadowRecord, dir))                                          \
  X(__builtin_offsetof(ShadowRecord, contribution)) X(__builtin_offsetof(ShadowRecord, pixel))              \
  X(sizeof(FilmAccumulate)) X(__builtin_offsetof(FilmAccumulate, pass_index))                               \
  X(__builtin_offsetof(FilmAccumulate, per_pixel)) X(__builtin_offsetof(FilmAccumulate, pass_count)) X(__builtin_offsetof(FilmAccumulate, colour_values))      \
  X(__builtin_offsetof(PathRecord, flags)) X(__builtin_offsetof(PathRecord, light_normal))                  \
  X(sizeof(ShadeParams)) X(__builtin_offsetof(ShadeParams, light_count))                                    \
  X(__builtin_offsetof(ShadeParams, min_weight))                                                            \
  X(sizeof(CameraGPU)) X(__builtin_offsetof(CameraGPU, lens)) X(__builtin_offsetof(CameraGPU, width))        \
  X(__builtin_offsetof(CameraGPU, pixel_count)) X(__builtin_offsetof(Material, roughness))                    \
  X(__builtin_offsetof(Material, metallic)) X(__builtin_offsetof(Material, roughness_texture)) X(__builtin_offsetof(Material, emission_texture)) X(__builtin_offsetof(Material, normal_texture)) X(__builtin_offsetof(Material, normal_scale)) X(sizeof(TriangleTangents)) X(sizeof(TriangleColours)) X(sizeof(TriangleAlpha)) X(__builtin_offsetof(TriangleAlpha, sampling)) X(__builtin_offsetof(Material, alpha_cutoff)) X(__builtin_offsetof(Material, volume)) X(__builtin_offsetof(Material, clearcoat_roughness_texture)) X(__builtin_offsetof(Material, clearcoat_alpha)) X(__builtin_offsetof(TriangleTangents, t1))               \
  X(sizeof(Material)) X(__builtin_offsetof(Material, specular_exponent))                                   \
  X(__builtin_offsetof(Material, texture)) X(sizeof(Sphere)) X(sizeof(Cylinder))    \
  X(sizeof(Triangle)) X(sizeof(TriangleShading)) X(__builtin_offsetof(TriangleShading, u2))               \
  X(sizeof(Texture)) X(__builtin_offsetof(Texture, scale)) X(__builtin_offsetof(Texture, sampling)) X(__builtin_offsetof(Texture, uv_v)) X(sizeof(BvhNode8))                             \
  X(__builtin_offsetof(BvhNode8, child)) X(__builtin_offsetof(BvhNode8, height)) X(sizeof(TriangleBlock4)) \
  X(__builtin_offsetof(TriangleBlock4, ref)) X(sizeof(Photon)) X(__builtin_offsetof(Photon, wi))               \
  X(__builtin_offsetof(Photon, power)) X(sizeof(PhotonGridParams))                                           \
  X(__builtin_offsetof(PhotonGridParams, cell_size)) X(__builtin_offsetof(PhotonGridParams, table_size))     \
  X(__builtin_offsetof(PhotonGridParams, photon_count)) X(sizeof(PhotonPassParams))                            \
  X(__builtin_offsetof(PhotonPassParams, alpha)) X(__builtin_offsetof(PhotonPassParams, footprint_radius))        \
  X(__builtin_offsetof(PhotonPassParams, first_photon)) X(__builtin_offsetof(PhotonPassParams, pixel_end))        \
  X(sizeof(VisiblePoint)) X(__builtin_offsetof(VisiblePoint, recorded)) X(__builtin_offsetof(VisiblePoint, depth))  \
  X(__builtin_offsetof(VisiblePoint, footprint)) X(__builtin_offsetof(VisiblePoint, beta))                         \
  X(__builtin_offsetof(VisiblePoint, kind)) X(__builtin_offsetof(VisiblePoint, alpha))                             \
  X(__builtin_offsetof(VisiblePoint, specular)) X(__builtin_offsetof(VisiblePoint, ior))                           \
  X(sizeof(SppmPixel)) X(__builtin_offsetof(SppmPixel, radius2)) X(__builtin_offsetof(SppmPixel, sum_r2))          \
  X(sizeof(cs_packed3)) X(__builtin_offsetof(Photon, bounces)) X(__builtin_offsetof(Photon, phong_scale))           \
  X(__builtin_offsetof(PathRecord, cone_width)) X(__builtin_offsetof(PathRecord, cone_spread))                      \
  X(sizeof(PhotonRecord)) X(__builtin_offsetof(PhotonRecord, power)) X(__builtin_offsetof(PhotonRecord, index))      \
  X(__builtin_offsetof(PhotonRecord, depth)) X(__builtin_offsetof(PhotonRecord, path_length))                       \
  X(__builtin_offsetof(PhotonRecord, flags)) X(__builtin_offsetof(ShadowRecord, tmax))                              \
  X(sizeof(PathParams)) X(__builtin_offsetof(PathParams, light_count)) X(__builtin_offsetof(PathParams, max_depth)) \
  X(__builtin_offsetof(PathParams, ray_capacity)) X(__builtin_offsetof(PathParams, first_pass))                     \
  X(__builtin_offsetof(PathParams, seed)) X(__builtin_offsetof(PathParams, strategy))                               \
  X(__builtin_offsetof(PathParams, rr_depth)) X(__builtin_offsetof(PathParams, sampler))                            \
  X(__builtin_offsetof(PathParams, wave_pixels)) X(__builtin_offsetof(PathParams, wave_samples)) \
  X(__builtin_offsetof(PathParams, environment_light))

#endif /* CAUSTICA_TESTS_RECORD_LAYOUT_H */
