#line 2 "kernels/integrator/path_stage_data.h"
/* What the path tracer's stage functions read and write besides the path
 * itself: the scene (lib/scene_buffers.h), the launch's PathParams, the
 * film, and what the features compiled in add (the photon map, the
 * numerics counters, the aux passes). Both shapes' kernels
 * (shade_surface_path.cl, trace_paths.cl) take PATH_STAGE_PARAMS and build
 * it once with PATH_STAGE_DATA; the host binds those parameters in one
 * place (host/render/integrator_path.cpp: bind_path_stage_data). */
#ifndef CAUSTICA_INTEGRATOR_PATH_STAGE_DATA_H
#define CAUSTICA_INTEGRATOR_PATH_STAGE_DATA_H

#include "lib/photon_grid.h"
#include "lib/film.h"
#include "lib/scene_buffers.h"

typedef struct {
  SceneBuffers scene;
  PathParams params;
  __global ulong* film;
  volatile __global uint* film_counters;
  uint film_high_offset;
#if HAS_CAUSTICS
  __global VisiblePoint* visible_points;
  uint record_visible_points; /* this pass traces a photon map: record the pixels' visible points */
  PhotonGridParams grid;
  __global const uint* grid_bucket_start;
  __global const Photon* grid_photons;
  float caustic_radius; /* 0: the photon pass is off in this pass */
  volatile __global ulong* gather_counters;
#endif
#if HAS_NUMERIC_CHECKS
  volatile __global ulong* numerics;
#endif
#if HAS_AUX_PASSES
  uint film_aux_offset;
#endif
} PathStageData;

#if HAS_CAUSTICS
#define PATH_CAUSTIC_PARAMS                                                                   \
  , __global VisiblePoint *restrict visible_points, uint record_visible_points, PHOTON_GRID_PARAMS, \
      float caustic_radius, volatile __global ulong *restrict gather_counters
#define PATH_CAUSTIC_ARGS , visible_points, record_visible_points, PHOTON_GRID_ARGS, caustic_radius, gather_counters
#else
#define PATH_CAUSTIC_PARAMS
#define PATH_CAUSTIC_ARGS
#endif
#if HAS_NUMERIC_CHECKS
#define PATH_NUMERICS_PARAMS , volatile __global ulong *restrict numerics
#define PATH_NUMERICS_ARGS , numerics
#else
#define PATH_NUMERICS_PARAMS
#define PATH_NUMERICS_ARGS
#endif
#if HAS_AUX_PASSES
#define PATH_AUX_PARAMS , uint film_aux_offset
#define PATH_AUX_ARGS , film_aux_offset
#else
#define PATH_AUX_PARAMS
#define PATH_AUX_ARGS
#endif

#define PATH_STAGE_PARAMS \
  SCENE_BUFFERS_PARAMS, PathParams params, FILM_PARAMS PATH_CAUSTIC_PARAMS PATH_NUMERICS_PARAMS PATH_AUX_PARAMS
#define PATH_STAGE_DATA(name) \
  const PathStageData name = {SCENE_BUFFERS_FROM_PARAMS, params, FILM_ARGS PATH_CAUSTIC_ARGS PATH_NUMERICS_ARGS PATH_AUX_ARGS}

/* The argument lists of the library functions written for parameter lists. */
#define FILM_OF(d) (d)->film, (d)->film_counters, (d)->film_high_offset
#define PHOTON_GRID_OF(d) (d)->grid, (d)->grid_bucket_start, (d)->grid_photons

#endif /* CAUSTICA_INTEGRATOR_PATH_STAGE_DATA_H */
