#line 2 "tests/kernels/stiff/random.h"
/* The stiff kernels' random numbers (stiff/self_intersection.cl,
 * stiff/shadow_rays.cl): stiff_unit_float(&state) draws from a per-work-item hash
 * chain; seed the state with mix32 of the work-item's index. Not lib/rng.h:
 * the ray sets only need to be reproducible, and these are the draws the
 * tests' counts were found with. */
#ifndef CAUSTICA_TESTS_STIFF_RANDOM_H
#define CAUSTICA_TESTS_STIFF_RANDOM_H

uint mix32(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return x;
}
float stiff_unit_float(uint* s) { *s = mix32(*s + 0x9e3779b9u); return (float)(*s >> 8) * 0x1.0p-24f; }

#endif /* CAUSTICA_TESTS_STIFF_RANDOM_H */
