#line 2 "kernels/lib/wave_samples.h"
/* Which pixel and sample index a wave sample is, and when a pixel's half
 * buffer restarts: compiled for the device and, through shared/compat.h,
 * for the host film (host/render/film.cpp), so the two cannot disagree.
 *
 * Rules: with every pixel alike (PathParams.wave_entries 0), wave sample s
 * is pixel pixel_offset + s % wave_pixels in pass first_pass + s /
 * wave_pixels. An uneven wave (adaptive sampling) lists its pixels in pixel
 * order, entry j owning wave samples [entry_offset[j], entry_offset[j + 1]):
 * wave sample s belongs to the entry found by binary search, and is that
 * pixel's sample pixel_spp[pixel] + (s - entry_offset[j]). Either way a
 * pixel's samples are the next indices of its own sequence, whatever slot
 * or order traces them. */
#ifndef CAUSTICA_LIB_WAVE_SAMPLES_H
#define CAUSTICA_LIB_WAVE_SAMPLES_H

#include "shared/compat.h"
#include "shared/types.h"

#define WAVE_ALLOCATION_PARAMS                                                          \
  __global const uint *restrict wave_entry_pixel, __global const uint *restrict wave_entry_offset, \
      __global const uint *restrict wave_pixel_spp
#define WAVE_ALLOCATION_ARGS wave_entry_pixel, wave_entry_offset, wave_pixel_spp

/* The half of a pixel with n samples restarts with a wave adding k when
 * [n, n + k) holds a power of two (never for n = 0: sample 0 is in no half). */
CS_DEVICE bool film_half_restarts(uint n, uint k) {
  if (n == 0u || k == 0u) return false;
  const uint last = n + k - 1u;
  return (1u << (31u - clz(last))) >= n; /* the largest power of two <= last is >= n */
}

#ifdef __OPENCL_VERSION__
/* Wave sample s: its pixel (*pixel) and its index in that pixel's sequence. */
inline uint wave_sample_index(const PathParams* params, uint pixel_offset, uint s, WAVE_ALLOCATION_PARAMS,
                              uint* pixel) {
  if (params->wave_entries == 0u) {
    *pixel = pixel_offset + s % params->wave_pixels;
    return params->first_pass + s / params->wave_pixels;
  }
  uint lo = 0u, hi = params->wave_entries - 1u; /* the last entry whose offset <= s */
  while (lo < hi) {
    const uint mid = (lo + hi + 1u) / 2u;
    if (wave_entry_offset[mid] <= s)
      lo = mid;
    else
      hi = mid - 1u;
  }
  *pixel = wave_entry_pixel[lo];
  return wave_pixel_spp[*pixel] + (s - wave_entry_offset[lo]);
}
#endif

#endif
