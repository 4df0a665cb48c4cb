#line 2 "kernels/shared/photon.h"
/* Photons and the photon hash grid, shared by the C++ host and OpenCL C
 * (issue 13: stochastic progressive photon mapping).
 *
 * Rules: as types.h (plain C, 16-byte multiples, explicit padding, layout
 * static_asserted in host/cl/layout_check.cpp and compared with the device
 * in tests/test_render_core.cpp), and every field one meaning: a scalar is
 * its own field, never a vector's spare lane (a point or direction that
 * shares 16 bytes with a scalar is a cs_packed3). The emit/trace stages write Photon records
 * plus an atomic count; the grid (kernels/photon/, host/render/photon_grid.h)
 * sorts them into hash buckets; the gather queries it (lib/photon_grid.h). */
#ifndef CAUSTICA_SHARED_PHOTON_H
#define CAUSTICA_SHARED_PHOTON_H

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#else
#include "kernels/shared/types.h"
#endif

/* Three floats, 12 bytes, 4-byte aligned: a point or direction that shares
 * 16 bytes with a scalar field (a float3 would take all 16). */
typedef struct {
  float x, y, z;
} cs_packed3;

inline float3 unpack3(cs_packed3 v) { return make_float3(v.x, v.y, v.z); }
inline cs_packed3 pack3(float3 v) {
  cs_packed3 p;
  p.x = v.x;
  p.y = v.y;
  p.z = v.z;
  return p;
}

/* A photon stored on a diffuse surface. */
typedef struct {
  cs_packed3 position;
  float bounces;     /* the specular bounces its light path took (the gather keeps paths within nbounces) */
  cs_packed3 wi;     /* unit direction toward where the photon came from */
  float phong_scale; /* what phong's gather multiplies the flux by (lib/caustics.h): d^2, 1 / pi or 1 */
  cs_float4 power;   /* rgb flux; w unused */
} Photon; /* 48 bytes */

/* The grid: cell (i, j, k) = floor((p - origin) * inv_cell_size) per axis,
 * hashed into table_size buckets (a power of two). Photons of one bucket lie
 * contiguously in the sorted photon array, ordered by their index in the
 * unsorted array: bucket b holds slots [bucket_start[b], bucket_start[b + 1]). */
typedef struct {
  cs_float4 origin;    /* xyz: the grid's min corner (the scene's); w unused */
  float cell_size;
  float inv_cell_size; /* 1 / cell_size: the one expression both build and query use */
  cs_uint table_size;  /* buckets, a power of two */
  cs_uint photon_count;
} PhotonGridParams; /* 32 bytes */

/* The grid's exclusive prefix sum: each work-item scans this many
 * consecutive values serially (kernels/photon/scan_bucket_counts.cl), so the
 * scan needs no local memory and works for any work-group size. */
#define PHOTON_SCAN_BLOCK 256u

/* Cell coordinates are clamped to +-this before conversion to int, so a
 * stray point far outside the scene (or NaN) still maps to a valid cell. */
#define PHOTON_GRID_CELL_LIMIT 1073741824.0f /* 2^30 */

/* Caustic casters: the surfaces photons are traced through (smooth or
 * glossy conductors and dielectrics with GGX alpha below this) and that the
 * path tracer, after its first receiving vertex, leaves to the photon map.
 * Every other surface (plastic, rougher metal and glass) receives photons.
 * 0.1 keeps the glossy caustics of polished metal and frosted glass sharp
 * enough for a radius-limited estimate while leaving wide lobes, which a
 * photon map blurs, to path tracing. */
#define CAUSTIC_CASTER_ALPHA 0.3f

/* A pixel's initial gather radius, in footprints of its camera path at its
 * first visible point (the ray cone's width there: the camera's angle per
 * pixel times the distance travelled, widened through curved mirrors and
 * glass and by glossy lobes; shade_surface_path). SPPM keeps the photons of
 * early passes in its estimate, so a wide start blurs a caustic for long:
 * on scenes/caustics.json two footprints left 2x the error of one after
 * 40 s. Sparse photons then speckle a little more at first. */
#define PHOTON_RADIUS_FOOTPRINTS 1.0f

/* Bounded work per gather (lib/photon_grid.h's photon_query_begin_bounded):
 * a visible point's gather (once per pixel and pass) reads at most about
 * this many photons, an inline gather at a later receiver (once per path
 * vertex) fewer. */
#define PHOTON_GATHER_MAX_VISITS 256u
#define PHOTON_INLINE_GATHER_MAX_VISITS 64u

/* Ray cones (shade_surface_path): a path's footprint width grows by its
 * spread angle times the distance; a diffuse lobe adds this much spread
 * (radians), a glossy one PATH_CONE_GLOSSY_SPREAD times its GGX alpha. The
 * inline gather at a later receiver uses the footprint there as its radius
 * (at most the pass's cap), so these set how far an indirect caustic is
 * blurred before the radii shrink. */
#define PATH_CONE_DIFFUSE_SPREAD 0.25f
#define PATH_CONE_GLOSSY_SPREAD 2.0f

/* The gathers' counters of one pass (ulong each, zeroed before the pass and
 * read after it, host/render/photon_pass.cpp): the visible points' radii
 * after their update, as a histogram of quarter octaves (bin = floor(4
 * log2 r) + 128, clamped to the table: the next pass's cells follow them),
 * the photons read (visits) by both kinds of gather, and histograms of the
 * visits per gather in bins of PHOTON_VISIT_BIN_WIDTH (the last bin holds
 * everything above). The gather counts are the histograms' sums. */
#define PHOTON_RADIUS_BINS 256u
#define PHOTON_VISIT_BINS 64u
#define PHOTON_VISIT_BIN_WIDTH 8u
#define GATHER_COUNT_RADIUS 0u
#define GATHER_COUNT_VISITS_D1 256u
#define GATHER_COUNT_VISITS_LATER 257u
#define GATHER_COUNT_HISTOGRAM_D1 258u
#define GATHER_COUNT_HISTOGRAM_LATER (258u + PHOTON_VISIT_BINS)
#define GATHER_COUNTERS (258u + 2u * PHOTON_VISIT_BINS)

/* One pass of photons (kernels/photon/emit_photons.cl, bounce_photons.cl,
 * gather_photons.cl). */
typedef struct {
  cs_uint photon_count; /* photon paths emitted this pass */
  cs_uint light_count;
  cs_uint pass_index;   /* decorrelates the passes' random numbers */
  cs_uint seed;
  cs_uint max_depth;    /* the scene's nbounces: scattering events of a whole path */
  cs_uint pixel_count;  /* gather: visible points */
  float alpha;          /* SPPM's radius reduction (2/3) */
  float radius_cap;     /* gather: the largest radius (one grid cell) */
  cs_uint footprint_radius; /* gather: 1: a pixel's radius starts at its footprint, 0: at radius_cap (--caustic-radius) */
  /* A process's share of the pass (host/render/pixel_share.h; one process:
   * all of it): emit traces photons [first_photon, photon_end) of the
   * photon_count, the gather pixels [first_pixel, pixel_end). */
  cs_uint first_photon, photon_end, first_pixel, pixel_end;
  cs_uint pad0, pad1, pad2;
} PhotonPassParams; /* 64 bytes */

/* Where a camera path first reached a receiving surface in this pass (one
 * per pixel, written by shade_surface_path, read and cleared by the
 * gather): the point, the frame and outgoing direction, the camera path's
 * throughput up to it, and the BSDF there (lib/bsdf.h's Bsdf, flattened). */
typedef struct {
  cs_packed3 position;
  cs_uint recorded;    /* 1 when recorded this pass, else 0 */
  cs_packed3 normal;   /* the shading frame's z (turned toward wo for opaque surfaces) */
  cs_uint depth;       /* the camera path's scattering events before it */
  cs_packed3 wo;       /* unit, toward the camera along the path */
  float footprint;     /* the camera path's footprint width there (its ray cone) */
  cs_packed3 beta;     /* rgb throughput of the camera path */
  cs_uint kind;        /* Bsdf.kind */
  cs_packed3 diffuse;  /* Bsdf.diffuse */
  float alpha;         /* Bsdf.alpha */
  cs_packed3 specular; /* Bsdf.specular */
  float ior;           /* Bsdf.ior */
} VisiblePoint; /* 96 bytes */

/* A pixel's SPPM statistics (Hachisuka & Jensen 2009): accumulated flux tau,
 * photon count N and squared radius (0 until its first visible point sets
 * it). The caustic radiance is tau / (passes * pi * radius2), photon powers
 * being per pass already. For the error estimate (issue 19), the sums over
 * the passes with a visible point of each pass's own estimate L_k = beta
 * sum_k / (pi r_k^2), of r_k^2 and of L_k^2 r_k^2: a pass's variance goes
 * as 1 / r_k^2 (its photon count as r_k^2), so their spread estimates the
 * variance the pixel's estimate has at its current radius
 * (host/render/photon_pass.cpp, add_variance_to). */
typedef struct {
  cs_float4 tau;     /* rgb; w unused */
  cs_float4 sum_l;   /* rgb sum of L_k; w unused */
  cs_float4 sum_l2;  /* rgb sum of L_k^2 r_k^2; w unused */
  float photons;     /* N */
  float radius2;
  float footprint2;  /* the squared initial radius (one footprint): scales the bias estimate */
  float sum_r2;      /* sum of r_k^2 */
} SppmPixel; /* 64 bytes */

#endif /* CAUSTICA_SHARED_PHOTON_H */
