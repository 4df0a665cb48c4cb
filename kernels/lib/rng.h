#line 2 "kernels/lib/rng.h"
/* Counter-based random numbers and low-discrepancy samples for the
 * stochastic integrators (path tracing, issue 11; photon emission later).
 *
 * Rules: no state is carried between work-items or launches; every number is
 * a pure function of (pixel, sample index, dimension, seed), so an image is
 * the same bits for any thread count, work-group size, chunking or device
 * order. Floats are 24-bit fractions in [0, 1): 1 itself never comes out.
 *
 * Samples are Sobol-Burley (Burley 2020, "Practical Hash-based Owen
 * Scrambling"): each pair of dimensions is the 2D Sobol (0,2)-sequence, its
 * index shuffled by a nested uniform scramble and its coordinates Owen
 * scrambled, both seeded by a hash of (pixel, dimension pair, seed). Within a
 * pixel any power-of-two prefix of the samples is a (0,m,2)-net (stratified
 * in every elementary interval); between pixels and between dimension pairs
 * the scrambles decorrelate them. */
#ifndef CAUSTICA_LIB_RNG_H
#define CAUSTICA_LIB_RNG_H

#include "shared/compat.h"
#include "shared/types.h"

/* The integer steps below are written once, as macros over a lane type T,
 * and instantiated for uint and for uint4: the shade stage draws a path
 * vertex's three dimension pairs in the lanes of one vector (see
 * sobol_burley_2d_x3), where scalar code spent about two fifths of the
 * stage's own time on these xor-shift-multiply chains. The uint4 forms are
 * the scalar ones lane by lane, so their bits are the same.
 *
 * hash_u32: a full-avalanche 32-bit mix ("lowbias32", C. Wellons): every
 * input bit flips each output bit with probability ~1/2. */
#define RNG_DEFINE_HASHES(T, SUFFIX)                                                                   \
  inline T hash_u32##SUFFIX(T x) {                                                                     \
    x ^= x >> 16;                                                                                      \
    x *= 0x21f0aaadu;                                                                                  \
    x ^= x >> 15;                                                                                      \
    x *= 0x735a2d97u;                                                                                  \
    x ^= x >> 15;                                                                                      \
    return x;                                                                                          \
  }                                                                                                    \
  inline T hash_combine##SUFFIX(T seed, T value) {                                                     \
    return hash_u32##SUFFIX(seed ^ (value + 0x9e3779b9u + (seed << 6) + (seed >> 2)));                 \
  }
RNG_DEFINE_HASHES(uint, )
RNG_DEFINE_HASHES(uint4, _x4)
#undef RNG_DEFINE_HASHES

inline uint hash3(uint a, uint b, uint c) { return hash_combine(hash_combine(hash_u32(a), b), c); }

/* The top 24 bits as a float in [0, 1). */
inline float unit_float(uint bits) { return (float)(bits >> 8) * 0x1.0p-24f; }

/* An independent uniform in [0, 1) for (key, counter): the plain random
 * sampler that the low-discrepancy one is compared against. */
inline float random_float(uint key, uint counter) { return unit_float(hash_combine(hash_u32(key), counter)); }

/* Bit permutations, again for uint and uint4 (lane by lane, the same bits):
 *  - reverse_bits_u32: the 32 bits in reverse order;
 *  - sobol_dimension1_reversed: dimension 1 of the 2D Sobol sequence (below)
 *    with its bits reversed, in bit-parallel form. XOR-ing v_k for the
 *    index's set bits: with bits reversed, v_k has bit j set iff
 *    binomial(k, j) is odd, i.e. (Lucas) iff j's bits are a subset of k's;
 *    so bit j of the reversed result is the XOR of the index bits k that are
 *    supersets of j, a superset-sum transform over the five bits of a bit
 *    position, one shift-and-xor per bit. Same values as the 32-step loop
 *    (tests/host/test_rng.cpp compares them) at a fraction of the cost;
 *  - laine_karras_permutation: Burley's hash-based Laine-Karras
 *    permutation, an Owen scramble of the bits of x seen from the least
 *    significant end (each bit flipped by a hash of the bits below it). */
#define RNG_DEFINE_BIT_PERMUTATIONS(T, SUFFIX)                                                         \
  inline T reverse_bits_u32##SUFFIX(T x) {                                                             \
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);                                           \
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);                                           \
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);                                           \
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);                                           \
    return (x >> 16) | (x << 16);                                                                      \
  }                                                                                                    \
  inline T sobol_dimension1_reversed##SUFFIX(T index) {                                                \
    T y = index;                                                                                       \
    y ^= (y >> 1) & 0x55555555u;                                                                       \
    y ^= (y >> 2) & 0x33333333u;                                                                       \
    y ^= (y >> 4) & 0x0F0F0F0Fu;                                                                       \
    y ^= (y >> 8) & 0x00FF00FFu;                                                                       \
    y ^= (y >> 16) & 0x0000FFFFu;                                                                      \
    return y;                                                                                          \
  }                                                                                                    \
  inline T laine_karras_permutation##SUFFIX(T x, T seed) {                                             \
    x += seed;                                                                                         \
    x ^= x * 0x6c50b47cu;                                                                              \
    x ^= x * 0xb82f1e52u;                                                                              \
    x ^= x * 0xc7afe638u;                                                                              \
    x ^= x * 0x8d22f6e6u;                                                                              \
    return x;                                                                                          \
  }
RNG_DEFINE_BIT_PERMUTATIONS(uint, )
RNG_DEFINE_BIT_PERMUTATIONS(uint4, _x4)
#undef RNG_DEFINE_BIT_PERMUTATIONS

/* The 2D Sobol sequence as 32-bit fractions: dimension 0 is the van der
 * Corput sequence (the index's bits reversed), dimension 1 uses the
 * direction numbers of the primitive polynomial x + 1 (v_1 = 2^31,
 * v_k = v_{k-1} ^ (v_{k-1} >> 1)). Together a (0,2)-sequence. */
inline uint sobol_dimension0(uint index) { return reverse_bits_u32(index); }
inline uint sobol_dimension1(uint index) { return reverse_bits_u32(sobol_dimension1_reversed(index)); }

/* Owen scrambling of a 32-bit fraction: each bit flipped by a hash of the
 * bits above it. Keeps every (0,m,2)-net a net. */
inline uint nested_uniform_scramble(uint x, uint seed) {
  return reverse_bits_u32(laine_karras_permutation(reverse_bits_u32(x), seed));
}

/* Sobol-Burley's bits for the dimension pair(s) seeded by pair_seed
 * (hash_combine(pixel_seed, pair)), sample `index`: dimension 2 pair as
 * returned, 2 pair + 1 in *y. shuffled = nested_uniform_scramble(index,
 * pair_seed); each output is nested_uniform_scramble(sobol_dimensionK(
 * shuffled), seed_K). Written out, the bit reversals that cancel
 * (reverse(reverse(v)) = v) are left out: four reversals instead of eight,
 * the same bits. Again for uint and for uint4 (SPLAT widens a uint). */
#define RNG_SPLAT_UINT(x) (x)
#define RNG_DEFINE_SOBOL_BURLEY_BITS(T, SUFFIX, SPLAT)                                                 \
  __attribute__((always_inline)) inline T sobol_burley_bits##SUFFIX(uint index, T pair_seed, T* y) {   \
    const T shuffled_reversed = laine_karras_permutation##SUFFIX(SPLAT(reverse_bits_u32(index)), pair_seed); \
    const T shuffled = reverse_bits_u32##SUFFIX(shuffled_reversed);                                    \
    /* sobol_dimension1(shuffled), reversed again inside the scramble */                               \
    *y = reverse_bits_u32##SUFFIX(laine_karras_permutation##SUFFIX(                                   \
        sobol_dimension1_reversed##SUFFIX(shuffled), hash_combine##SUFFIX(pair_seed, SPLAT(0xdecafbadu)))); \
    /* sobol_dimension0(shuffled) = shuffled_reversed, reversed again inside the scramble */          \
    return reverse_bits_u32##SUFFIX(                                                                   \
        laine_karras_permutation##SUFFIX(shuffled, hash_combine##SUFFIX(pair_seed, SPLAT(0x5ca1ab1eu)))); \
  }
RNG_DEFINE_SOBOL_BURLEY_BITS(uint, , RNG_SPLAT_UINT)
RNG_DEFINE_SOBOL_BURLEY_BITS(uint4, _x4, splat_uint4)
#undef RNG_DEFINE_SOBOL_BURLEY_BITS
#undef RNG_SPLAT_UINT

/* Sample `index` of the pixel's sequence in dimensions (2 pair, 2 pair + 1).
 * pixel_seed mixes the pixel and the user's seed (hash3(pixel, 0, seed)). */
__attribute__((always_inline)) inline float2 sobol_burley_2d(uint index, uint pair, uint pixel_seed) {
  uint y;
  const uint x = sobol_burley_bits(index, hash_combine(pixel_seed, pair), &y);
  return make_float2(unit_float(x), unit_float(y));
}

/* Pairs first_pair, first_pair + 1 and first_pair + 2 of sample `index`:
 * the same bits as three sobol_burley_2d calls, each step done once for the
 * three pairs in the lanes of a uint4 (the fourth lane is computed and
 * dropped). A path vertex draws its three pairs here. */
__attribute__((always_inline)) inline void sobol_burley_2d_x3(uint index, uint first_pair, uint pixel_seed,
                                                              float2* pair0, float2* pair1, float2* pair2) {
  uint4 y;
  const uint4 x = sobol_burley_bits_x4(
      index, hash_combine_x4(splat_uint4(pixel_seed), make_uint4(0u, 1u, 2u, 3u) + first_pair), &y);
  *pair0 = make_float2(unit_float(x.x), unit_float(y.x));
  *pair1 = make_float2(unit_float(x.y), unit_float(y.y));
  *pair2 = make_float2(unit_float(x.z), unit_float(y.z));
}

/* The 2D sample of dimension pair `pair` for sample `index` of the pixel
 * whose seed is pixel_seed, from the chosen sampler (SAMPLER_*, types.h). */
__attribute__((always_inline)) inline float2 pixel_sample_2d(uint sampler, uint index, uint pair,
                                                            uint pixel_seed) {
  if (sampler == SAMPLER_INDEPENDENT) {
    const uint key = hash_combine(pixel_seed, index);
    return make_float2(random_float(key, 2u * pair), random_float(key, 2u * pair + 1u));
  }
  return sobol_burley_2d(index, pair, pixel_seed);
}

/* pixel_sample_2d for pairs first_pair, first_pair + 1, first_pair + 2. */
__attribute__((always_inline)) inline void pixel_samples_2d_x3(uint sampler, uint index, uint first_pair,
                                                               uint pixel_seed, float2* pair0, float2* pair1,
                                                               float2* pair2) {
  if (sampler == SAMPLER_INDEPENDENT) {
    *pair0 = pixel_sample_2d(sampler, index, first_pair, pixel_seed);
    *pair1 = pixel_sample_2d(sampler, index, first_pair + 1u, pixel_seed);
    *pair2 = pixel_sample_2d(sampler, index, first_pair + 2u, pixel_seed);
    return;
  }
  sobol_burley_2d_x3(index, first_pair, pixel_seed, pair0, pair1, pair2);
}

#endif /* CAUSTICA_LIB_RNG_H */
