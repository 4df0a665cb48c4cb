#line 2 "kernels/integrator_path.cl"
/* The path tracer's program: generate_camera_samples ->
 * { intersect_closest -> shade_surface_path -> intersect_shadow }* and the
 * film's pass accumulation (host/render/integrator_path.cpp drives it). */

#include "integrator/generate_camera_samples.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface_path.cl"
#include "integrator/intersect_shadow.cl"
#include "film/accumulate_film_pass.cl"
