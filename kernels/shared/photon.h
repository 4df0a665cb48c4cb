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
  cs_float4 position; /* xyz; w unused (0) */
  cs_float4 wi;       /* xyz unit direction toward where the photon came from; w unused */
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

#endif /* CAUSTICA_SHARED_PHOTON_H */
