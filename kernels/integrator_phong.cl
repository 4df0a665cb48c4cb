#line 2 "kernels/integrator_phong.cl"
/* The Whitted (phong) integrator's program: generate_camera_rays ->
 * { intersect_closest -> shade_surface_phong -> intersect_shadow }* and the
 * film's pass accumulation (host/render/integrator_phong.cpp drives it). */

#include "integrator/generate_camera_rays.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface_phong.cl"
#include "integrator/intersect_shadow.cl"
#include "film/accumulate_film_pass.cl"
