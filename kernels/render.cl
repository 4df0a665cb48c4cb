#line 2 "kernels/render.cl"
/* The wavefront program: every stage kernel in one build, so one scene
 * feature set means one compile and one cache entry. The stages are
 * generate_camera_rays -> intersect_closest -> shade_surface ->
 * intersect_shadow (see host/render/wavefront.cpp for the loop). */

#include "integrator/generate_camera_rays.cl"
#include "integrator/intersect_closest.cl"
#include "integrator/shade_surface.cl"
#include "integrator/intersect_shadow.cl"
