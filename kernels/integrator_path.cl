#line 2 "kernels/integrator_path.cl"
/* The path tracer's program: generate_camera_samples ->
 * { intersect_closest -> shade_surface_path -> intersect_shadow }* and the
 * film's pass accumulation (host/render/integrator_path.cpp drives it);
 * on CPUs the same stages as one kernel, trace_paths (issue 39);
 * with -DHAS_CAUSTICS=1 also the photon pass (host/render/
 * photon_pass.cpp): emit_photons -> { intersect_closest -> bounce_photons }*
 * -> compact_photons -> the grid's build -> gather_photons. */

#include "integrator/generate_camera_samples.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface_path.cl"
#include "integrator/intersect_shadow.cl"
#include "integrator/trace_paths.cl"
#include "film/accumulate_film_pass.cl"
/* The photon pass's stages, only in programs that run it. */
#if HAS_CAUSTICS
#include "photon/emit_photons.cl"
#include "photon/bounce_photons.cl"
#include "photon/trace_photons.cl"
#include "photon/compact_photons.cl"
#include "photon_grid.cl"
#include "photon/gather_photons.cl"
#endif
