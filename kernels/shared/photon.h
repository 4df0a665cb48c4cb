#line 2 "kernels/shared/photon.h"
/* Photons and the photon hash grid, shared by the C++ host and OpenCL C
 * (issue 13: stochastic progressive photon mapping).
 *
 * Rules: as types.h (plain C, 16-byte multiples, explicit padding, layout
 * static_asserted in host/cl/layout_check.cpp and compared with the device
 * in tests/test_render_core.cpp). The emit/trace stages write Photon records
 * plus an atomic count; the grid (kernels/photon/, host/render/photon_grid.h)
 * sorts them into hash buckets; the gather queries it (lib/photon_grid.h). */
#ifndef CAUSTICA_SHARED_PHOTON_H
#define CAUSTICA_SHARED_PHOTON_H

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#else
#include "kernels/shared/types.h"
#endif

/* A photon stored on a diffuse surface. */
typedef struct {
  cs_float4 position; /* xyz; w: the specular bounces it took (the gather keeps paths within nbounces) */
  cs_float4 wi;       /* xyz unit direction toward where the photon came from; w: length travelled from the light */
  cs_float4 power;    /* rgb flux; w unused */
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

/* A pixel's initial gather radius, in pixel footprints at its first visible
 * point (capped by PhotonPassParams.radius_cap). SPPM keeps the photons of
 * early passes in its estimate, so a wide start blurs a caustic for long:
 * on scenes/caustics.json two footprints (or the cap at 1% of the scene)
 * left 2x the error of one footprint (capped at 0.5%) after 40 s. Sparse
 * photons then speckle a little more at first. */
#define PHOTON_RADIUS_FOOTPRINTS 1.0f

/* One pass of photons (kernels/photon/emit_photons.cl, bounce_photons.cl,
 * gather_photons.cl). */
typedef struct {
  cs_float4 camera;     /* gather: xyz the camera's position, w its angle per pixel (0: radius_cap for all) */
  cs_uint photon_count; /* photon paths emitted this pass */
  cs_uint light_count;
  cs_uint pass_index;   /* decorrelates the passes' random numbers */
  cs_uint seed;
  cs_uint max_depth;    /* the scene's nbounces: scattering events of a whole path */
  cs_uint pixel_count;  /* gather: visible points */
  float alpha;          /* SPPM's radius reduction (2/3) */
  float radius_cap;     /* gather: the largest initial radius */
} PhotonPassParams; /* 48 bytes */

/* Where a camera path first reached a receiving surface in this pass (one
 * per pixel, written by shade_surface_path, read and cleared by the
 * gather): the point, the frame and outgoing direction, the camera path's
 * throughput up to it, and the BSDF there (lib/bsdf.h's Bsdf, flattened). */
typedef struct {
  cs_float4 position; /* xyz; w: 1 when recorded this pass, else 0 */
  cs_float4 normal;   /* the shading frame's z (turned toward wo for opaque surfaces); w: camera depth */
  cs_float4 wo;       /* xyz unit, toward the camera along the path */
  cs_float4 beta;     /* rgb throughput of the camera path */
  cs_float4 diffuse;  /* Bsdf.diffuse; w: Bsdf.alpha */
  cs_float4 specular; /* Bsdf.specular; w: Bsdf.ior */
  cs_uint kind;       /* Bsdf.kind */
  cs_uint pad0, pad1, pad2;
} VisiblePoint; /* 112 bytes */

/* A pixel's SPPM statistics (Hachisuka & Jensen 2009): accumulated flux tau,
 * photon count N and squared radius (0 until its first visible point sets
 * it). The caustic radiance is tau / (passes * pi * radius2), photon powers
 * being per pass already. */
typedef struct {
  cs_float4 tau;  /* rgb; w unused */
  float photons;  /* N */
  float radius2;
  cs_uint pad0, pad1;
} SppmPixel; /* 32 bytes */

#endif /* CAUSTICA_SHARED_PHOTON_H */
