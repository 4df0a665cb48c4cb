#line 2 "kernels/photon_pass.cl"
/* The photon pass's program (issue 13, SPPM): for now the hash grid's build,
 * count_bucket_photons -> scan_bucket_counts -> scatter_photon_indices ->
 * sort_bucket_photons -> copy_sorted_photons (host/render/photon_grid.cpp
 * drives it). Photon emission and tracing and the gather join it later. */

#include "photon/count_bucket_photons.cl"
#include "photon/scan_bucket_counts.cl"
#include "photon/scatter_photon_indices.cl"
#include "photon/sort_bucket_photons.cl"
#include "photon/copy_sorted_photons.cl"
