#line 2 "kernels/photon_grid.cl"
/* The photon hash grid's build (issue 13, SPPM): count_bucket_photons ->
 * scan_bucket_counts -> scatter_photon_indices -> sort_bucket_photons ->
 * copy_sorted_photons (host/render/photon_grid.cpp drives it). A program of
 * its own for the grid's tests; the path tracer's program includes it with
 * the rest of the photon pass (integrator_path.cl). */

#include "photon/count_bucket_photons.cl"
#include "photon/scan_bucket_counts.cl"
#include "photon/scatter_photon_indices.cl"
#include "photon/sort_bucket_photons.cl"
#include "photon/copy_sorted_photons.cl"
