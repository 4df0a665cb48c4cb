#line 2 "kernels/integrator_binary.cl"
/* The binary integrator's program: generate_camera_rays ->
 * intersect_closest -> shade_surface_binary, and the film's pass
 * accumulation (host/render/integrator_binary.cpp drives it). One program per
 * integrator and feature set: one compile and one cache entry each. */

#include "integrator/generate_camera_rays.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface_binary.cl"
#include "film/accumulate_film_pass.cl"
