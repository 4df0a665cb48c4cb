#line 2 "kernels/integrator_phong.cl"
/* The Whitted (phong) integrator's program: generate_camera_rays ->
 * { intersect_closest -> shade_surface_phong -> intersect_shadow }* and the
 * film's pass accumulation (host/render/integrator_phong.cpp drives it);
 * with -DHAS_CAUSTICS=1 (--caustics on) also the photon pass's
 * tracing and grid (emit_photons -> { intersect_closest -> bounce_photons }*
 * -> compact_photons -> the grid), which shade_surface_phong gathers from. */

#include "integrator/generate_camera_rays.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface_phong.cl"
#include "integrator/intersect_shadow.cl"
#include "film/accumulate_film_pass.cl"
/* The scene as the photon stages read it: included here, outside the #if,
 * so that the stages' own includes find it inlined once already. */
#include "lib/scene_buffers.h"
/* The photon pass's stages, only in programs that run it. */
#if HAS_CAUSTICS
#include "photon/emit_photons.cl"
#include "photon/bounce_photons.cl"
#include "photon/trace_photons.cl"
#include "photon/compact_photons.cl"
#include "photon_grid.cl"
#endif
