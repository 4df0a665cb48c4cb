#line 2 "kernels/lib/photon_grid.h"
/* The photon hash grid on the device: cells, buckets and the neighbour query
 * (built by kernels/photon/, host/render/photon_grid.h).
 *
 * Rules: a photon's cell is photon_grid_cell of its stored position, the one
 * float expression used by the build and by the query, so both agree even
 * for photons exactly on cell borders. A query visits every cell overlapping
 * its sphere; two of those cells may hash to the same bucket, so a photon is
 * handed out only while its own cell is being visited: each photon at most
 * once. Within a bucket photons lie in the order of their unsorted index, so
 * a caller that sums in query order gets the same bits on any device, thread
 * count or work-group size. Distances are fused multiply-adds written out,
 * so the host can repeat them exactly (tests/test_photon_grid.cpp).
 *
 * Use (OpenCL C has no lambdas, hence an iterator):
 *
 *   __kernel void gather(PHOTON_GRID_PARAMS, ...) {
 *     PhotonQuery query = photon_query_begin(PHOTON_GRID_ARGS, p, radius);
 *     for (int slot; (slot = photon_query_next(&query, PHOTON_GRID_ARGS)) >= 0;) {
 *       const Photon photon = grid_photons[slot];
 *       ...
 *     }
 *   }
 *
 * A query visits (2 radius / cell_size + 1)^3 cells or so: callers keep the
 * radius within one cell, 2 x 2 x 2 cells at most (host/render/photon_pass.h
 * sizes the cells from the radii queried and caps the radii at one cell).
 * The render's gathers do not use this iterator but direct loops over the
 * cells with a bound on their work (lib/caustics.h, gather_photon_flux):
 * PoCL keeps the iterator's state in memory, which made a gather cost
 * about two camera rays. */
#ifndef CAUSTICA_LIB_PHOTON_GRID_H
#define CAUSTICA_LIB_PHOTON_GRID_H

#include "lib/rng.h"
#include "shared/photon.h"

/* The grid a kernel queries (host: PhotonGrid::bind). */
#define PHOTON_GRID_PARAMS \
  PhotonGridParams grid, __global const uint* restrict grid_bucket_start, __global const Photon* restrict grid_photons
#define PHOTON_GRID_ARGS grid, grid_bucket_start, grid_photons

inline int3 photon_grid_cell(PhotonGridParams grid, float3 p) {
  const float3 c = floor((p - grid.origin.xyz) * grid.inv_cell_size);
  /* fmin/fmax, not clamp: they also turn NaN into a bound. */
  return convert_int3(fmin(fmax(c, -PHOTON_GRID_CELL_LIMIT), PHOTON_GRID_CELL_LIMIT));
}

/* Teschner et al.'s primes mixed by one hash_u32: a third of hash3's work,
 * which the gathers' bucket reads were spending most of their time on. */
inline uint photon_grid_bucket(PhotonGridParams grid, int3 cell) {
  return hash_u32(((uint)cell.x * 73856093u) ^ ((uint)cell.y * 19349663u) ^ ((uint)cell.z * 83492791u)) &
         (grid.table_size - 1u);
}

/* |a - b|^2 by explicit fmas, so that the host (tests/test_photon_grid.cpp,
 * which calls this function) rounds exactly as every device does. */
inline float photon_distance2(float3 a, float3 b) {
  const float3 d = a - b;
  return fma(d.z, d.z, fma(d.y, d.y, d.x * d.x));
}

typedef struct {
  float3 center;
  float radius2;
  int3 lo, hi; /* the cells overlapping the sphere, inclusive */
  int3 cell;   /* being visited */
  uint slot;   /* next slot of its bucket */
  uint end;    /* one past its bucket's last slot */
} PhotonQuery;

inline void photon_query_enter_cell(PhotonQuery* query, PHOTON_GRID_PARAMS) {
  const uint bucket = photon_grid_bucket(grid, query->cell);
  query->slot = grid_bucket_start[bucket];
  query->end = grid_bucket_start[bucket + 1u];
}

/* Photons with |position - center|^2 <= radius^2 (radius >= 0). */
inline PhotonQuery photon_query_begin(PHOTON_GRID_PARAMS, float3 center, float radius) {
  PhotonQuery query;
  query.center = center;
  query.radius2 = radius * radius;
  /* The distance test runs in floats and may accept a photon a few ulps
   * beyond the radius; a range widened by 1e-5 of it still covers that
   * photon's cell (an extra cell costs only its tests). */
  const float reach = radius * 1.00001f;
  query.lo = photon_grid_cell(grid, center - reach);
  query.hi = photon_grid_cell(grid, center + reach);
  query.cell = query.lo;
  photon_query_enter_cell(&query, PHOTON_GRID_ARGS);
  return query;
}

/* The next photon's slot in grid_photons, or -1 when there are no more. */
inline int photon_query_next(PhotonQuery* query, PHOTON_GRID_PARAMS) {
  for (;;) {
    while (query->slot < query->end) {
      const uint slot = query->slot++;
      const float3 position = unpack3(grid_photons[slot].position);
      if (photon_distance2(position, query->center) > query->radius2) continue;
      /* A photon of another cell hashed to this bucket: handed out when its
       * own cell is visited (if that cell is in range at all), never twice. */
      if (any(photon_grid_cell(grid, position) != query->cell)) continue;
      return (int)slot;
    }
    if (++query->cell.x > query->hi.x) {
      query->cell.x = query->lo.x;
      if (++query->cell.y > query->hi.y) {
        query->cell.y = query->lo.y;
        ++query->cell.z;
      }
    }
    if (query->cell.z > query->hi.z) return -1; /* every cell visited (and stays so on later calls) */
    photon_query_enter_cell(query, PHOTON_GRID_ARGS);
  }
}

#endif /* CAUSTICA_LIB_PHOTON_GRID_H */
