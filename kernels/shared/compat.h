#line 2 "kernels/shared/compat.h"
/* One source for host and device: what kernels/lib/ and kernels/shared/
 * need to compile as C++17 as well as OpenCL C 1.2, each mapped once here
 * (Cycles' kernel_compat_cpu.h / kernel_compat_opencl.h, in one file).
 *
 * Rules for code meant for both sides:
 *  - vector values are built with make_float3(x, y, z), splat_float3(s),
 *    make_float4_xyz(v, w) and their kin, never with OpenCL's
 *    (float3)(x, y, z) literal, which C++ parses as a cast of a comma
 *    expression;
 *  - swizzles are read-only and limited to .xyz and .xy (float4, float3)
 *    and .lo / .hi (float8): on the host they are union members, and
 *    writing one would also write the padding lane behind it;
 *  - address spaces are written __global / __constant / __local (empty on
 *    the host); functions in headers are `inline`, or CS_DEVICE where the
 *    device's inlining should stay the compiler's choice (CS_DEVICE is
 *    nothing on the device and `inline` on the host, as one definition per
 *    program must be);
 *  - the builtins below are the ones the library uses; a new one is added
 *    here, once, with OpenCL's definition.
 * The host side follows OpenCL's semantics where the library relies on
 * them: comparisons of vectors give int vectors of -1 / 0, select() picks
 * by the most significant bit, float3 is 16 bytes with a 16-byte
 * alignment (so records and Bsdf lay out as on the device), clamp is
 * fmin(fmax(x, lo), hi). Host code that includes this (through
 * shared/types.h) also gets these names in the global namespace; glm's own
 * functions take glm types and are found for those by argument lookup. */
#ifndef CAUSTICA_SHARED_COMPAT_H
#define CAUSTICA_SHARED_COMPAT_H

/* The feature flags' defaults (HAS_*, always 0 or 1) for code that reads
 * them; the runtime names every flag in a program's options anyway. */
#ifdef __OPENCL_C_VERSION__
#include "shared/feature_flags.h"
#else
#include "kernels/shared/feature_flags.h"
#endif

#ifdef __OPENCL_C_VERSION__

#define CS_DEVICE
/* Fixed arity: OpenCL C before 3.0 has no variadic macros (NVIDIA's
 * compiler refuses them), so a splat has its own name. */
#define make_float2(x, y) ((float2)(x, y))
#define make_float3(x, y, z) ((float3)(x, y, z))
#define make_float4(x, y, z, w) ((float4)(x, y, z, w))
#define make_float4_xyz(xyz, w) ((float4)(xyz, w))
#define make_int2(x, y) ((int2)(x, y))
#define make_int3(x, y, z) ((int3)(x, y, z))
#define make_int4(x, y, z, w) ((int4)(x, y, z, w))
#define make_uint2(x, y) ((uint2)(x, y))
#define make_uint4(x, y, z, w) ((uint4)(x, y, z, w))
#define splat_float2(s) ((float2)(s))
#define splat_float3(s) ((float3)(s))
#define splat_float4(s) ((float4)(s))
#define splat_float8(s) ((float8)(s))
#define splat_int4(s) ((int4)(s))
#define splat_uint4(s) ((uint4)(s))

#else /* C++17 on the host */

#include <math.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#define CS_DEVICE inline
#define __global
#define __constant
#define __local
#define __private
#define restrict __restrict__

typedef unsigned char uchar;
typedef unsigned short ushort;
typedef unsigned int uint;
typedef unsigned long ulong;
static_assert(sizeof(ulong) == 8, "OpenCL's ulong is 64 bits");

#ifndef M_PI_F
#define M_PI_F 3.14159274101257f
#define M_PI_2_F 1.57079637050629f
#define M_PI_4_F 0.78539818525314f
#define M_1_PI_F 0.31830987334251f
#define M_2_PI_F 0.63661974668503f
#endif

/* Vector types: unions of a component struct (first, so that T{x, y, z}
 * initialises it), the read-only swizzles, and s[], the lanes by index. */
union alignas(8) float2 {
  struct { float x, y; };
  float s[2];
};
union alignas(16) float3 {
  struct { float x, y, z; };
  float2 xy;
  float s[4]; /* s[3]: padding, as on the device */
};
union alignas(16) float4 {
  struct { float x, y, z, w; };
  float3 xyz;
  float2 xy;
  float s[4];
};
union alignas(32) float8 {
  float s[8];
  struct { float4 lo, hi; };
};
/* The 32-bit integer vectors, alike for int and uint. */
#define CS_INTEGER_VECTORS(E)                  \
  union alignas(8) E##2 {                      \
    struct { E x, y; };                        \
    E s[2];                                    \
  };                                           \
  union alignas(16) E##3 {                     \
    struct { E x, y, z; };                     \
    E s[4]; /* s[3]: padding */                \
  };                                           \
  union alignas(16) E##4 {                     \
    struct { E x, y, z, w; };                  \
    E s[4];                                    \
  };                                           \
  union alignas(32) E##8 {                     \
    E s[8];                                    \
  };
CS_INTEGER_VECTORS(int)
CS_INTEGER_VECTORS(uint)
#undef CS_INTEGER_VECTORS
union alignas(32) double4 {
  struct { double x, y, z, w; };
  double s[4];
};
union alignas(4) char4 {
  signed char s[4];
};
union alignas(8) char8 {
  signed char s[8];
};

/* Lane type, lane count and comparison-mask type of each vector type. */
template <class V> struct cs_vector { static constexpr int lanes = 0; };
#define CS_VECTOR(V, E, N, M)          \
  template <> struct cs_vector<V> {    \
    typedef E element;                 \
    typedef M mask;                    \
    static constexpr int lanes = N;    \
  };
CS_VECTOR(float2, float, 2, int2)
CS_VECTOR(float3, float, 3, int3)
CS_VECTOR(float4, float, 4, int4)
CS_VECTOR(float8, float, 8, int8)
CS_VECTOR(int2, int, 2, int2)
CS_VECTOR(int3, int, 3, int3)
CS_VECTOR(int4, int, 4, int4)
CS_VECTOR(int8, int, 8, int8)
CS_VECTOR(uint2, uint, 2, int2)
CS_VECTOR(uint3, uint, 3, int3)
CS_VECTOR(uint4, uint, 4, int4)
CS_VECTOR(double4, double, 4, int4)
CS_VECTOR(char4, signed char, 4, char4)
CS_VECTOR(char8, signed char, 8, char8)
#undef CS_VECTOR

template <class V> constexpr bool cs_is_vector = cs_vector<V>::lanes > 0;
template <class V> using cs_if_vector = std::enable_if_t<cs_is_vector<V>, int>;
template <class V, class S>
using cs_if_vector_scalar = std::enable_if_t<cs_is_vector<V> && std::is_arithmetic<S>::value, int>;
template <class V> using cs_element = typename cs_vector<V>::element;

/* A vector of the lanes f(i) (lanes past the count, padding, stay 0). */
template <class V, class F> inline V cs_lanes(F f) {
  V r{};
  for (int i = 0; i < cs_vector<V>::lanes; ++i) r.s[i] = f(i);
  return r;
}
template <class V> inline V cs_splat(cs_element<V> v) {
  return cs_lanes<V>([&](int) { return v; });
}

/* make_*: OpenCL's vector literals from their lanes; splat_*: from one
 * scalar (the device side's macros above, as functions). */
inline float2 make_float2(float x, float y) { return float2{x, y}; }
inline float3 make_float3(float x, float y, float z) { return float3{x, y, z}; }
inline float4 make_float4(float x, float y, float z, float w) { return float4{x, y, z, w}; }
inline float4 make_float4_xyz(float3 v, float w) { return float4{v.x, v.y, v.z, w}; }
inline int2 make_int2(int x, int y) { return int2{x, y}; }
inline int3 make_int3(int x, int y, int z) { return int3{x, y, z}; }
inline int4 make_int4(int x, int y, int z, int w) { return int4{x, y, z, w}; }
inline uint2 make_uint2(uint x, uint y) { return uint2{x, y}; }
inline uint4 make_uint4(uint x, uint y, uint z, uint w) { return uint4{x, y, z, w}; }
inline float2 splat_float2(float s) { return cs_splat<float2>(s); }
inline float3 splat_float3(float s) { return cs_splat<float3>(s); }
inline float4 splat_float4(float s) { return cs_splat<float4>(s); }
inline float8 splat_float8(float s) { return cs_splat<float8>(s); }
inline int4 splat_int4(int s) { return cs_splat<int4>(s); }
inline uint4 splat_uint4(uint s) { return cs_splat<uint4>(s); }

/* Arithmetic, lane by lane; a scalar operand is widened to every lane. */
#define CS_BINARY(op)                                                                               \
  template <class V, cs_if_vector<V> = 0> inline V operator op(V a, V b) {                          \
    return cs_lanes<V>([&](int i) { return cs_element<V>(a.s[i] op b.s[i]); });                    \
  }                                                                                                 \
  template <class V, class S, cs_if_vector_scalar<V, S> = 0> inline V operator op(V a, S b) {       \
    return cs_lanes<V>([&](int i) { return cs_element<V>(a.s[i] op cs_element<V>(b)); });          \
  }                                                                                                 \
  template <class V, class S, cs_if_vector_scalar<V, S> = 0> inline V operator op(S a, V b) {       \
    return cs_lanes<V>([&](int i) { return cs_element<V>(cs_element<V>(a) op b.s[i]); });          \
  }                                                                                                 \
  template <class V, class B, cs_if_vector<V> = 0> inline V& operator op##=(V& a, B b) { return a = a op b; }
CS_BINARY(+)
CS_BINARY(-)
CS_BINARY(*)
CS_BINARY(/)
CS_BINARY(&)
CS_BINARY(|)
CS_BINARY(^)
CS_BINARY(<<)
CS_BINARY(>>)
#undef CS_BINARY
template <class V, cs_if_vector<V> = 0> inline V operator-(V a) {
  return cs_lanes<V>([&](int i) { return cs_element<V>(-a.s[i]); });
}
template <class V, cs_if_vector<V> = 0> inline V operator~(V a) {
  return cs_lanes<V>([&](int i) { return cs_element<V>(~a.s[i]); });
}

/* Comparisons give the mask type, -1 where true and 0 where false. */
#define CS_COMPARE(op)                                                                                   \
  template <class V, cs_if_vector<V> = 0> inline typename cs_vector<V>::mask operator op(V a, V b) {          \
    return cs_lanes<typename cs_vector<V>::mask>([&](int i) { return a.s[i] op b.s[i] ? -1 : 0; });           \
  }                                                                                                          \
  template <class V, class S, cs_if_vector_scalar<V, S> = 0>                                                 \
  inline typename cs_vector<V>::mask operator op(V a, S b) {                                                 \
    return cs_lanes<typename cs_vector<V>::mask>([&](int i) { return a.s[i] op cs_element<V>(b) ? -1 : 0; }); \
  }                                                                                                          \
  template <class V, class S, cs_if_vector_scalar<V, S> = 0>                                                 \
  inline typename cs_vector<V>::mask operator op(S a, V b) {                                                 \
    return cs_lanes<typename cs_vector<V>::mask>([&](int i) { return cs_element<V>(a) op b.s[i] ? -1 : 0; }); \
  }
CS_COMPARE(<)
CS_COMPARE(>)
CS_COMPARE(<=)
CS_COMPARE(>=)
CS_COMPARE(==)
CS_COMPARE(!=)
#undef CS_COMPARE

/* Lane-wise forms of the scalar math functions. */
#define CS_LANEWISE1(f)                                                               \
  template <class V, cs_if_vector<V> = 0> inline V f(V a) {                           \
    return cs_lanes<V>([&](int i) { return ::f(a.s[i]); });                           \
  }
#define CS_LANEWISE2(f)                                                                   \
  template <class V, cs_if_vector<V> = 0> inline V f(V a, V b) {                          \
    return cs_lanes<V>([&](int i) { return ::f(a.s[i], b.s[i]); });                       \
  }                                                                                       \
  template <class V, class S, cs_if_vector_scalar<V, S> = 0> inline V f(V a, S b) {       \
    return cs_lanes<V>([&](int i) { return ::f(a.s[i], cs_element<V>(b)); });             \
  }
CS_LANEWISE1(fabs)
CS_LANEWISE1(sqrt)
CS_LANEWISE1(floor)
CS_LANEWISE2(fmin)
CS_LANEWISE2(fmax)
CS_LANEWISE2(copysign)
template <class V, cs_if_vector<V> = 0> inline V fma(V a, V b, V c) {
  return cs_lanes<V>([&](int i) { return ::fma(a.s[i], b.s[i], c.s[i]); });
}
#undef CS_LANEWISE1
#undef CS_LANEWISE2

inline int min(int a, int b) { return a < b ? a : b; }
inline int max(int a, int b) { return a > b ? a : b; }
inline uint min(uint a, uint b) { return a < b ? a : b; }
inline uint max(uint a, uint b) { return a > b ? a : b; }

/* OpenCL: clamp(x, lo, hi) = fmin(fmax(x, lo), hi); mix(a, b, t) = a + (b - a) t. */
inline float clamp(float x, float lo, float hi) { return fminf(fmaxf(x, lo), hi); }
template <class V, class B, cs_if_vector<V> = 0> inline V clamp(V x, B lo, B hi) { return fmin(fmax(x, lo), hi); }
inline float mix(float a, float b, float t) { return a + (b - a) * t; }
template <class V, class T, cs_if_vector<V> = 0> inline V mix(V a, V b, T t) { return a + (b - a) * t; }

inline float sincos(float x, float* cos_x) {
  *cos_x = cosf(x);
  return sinf(x);
}
inline float rsqrt(float x) { return 1.0f / sqrtf(x); }

template <class V, cs_if_vector<V> = 0> inline float dot(V a, V b) {
  float sum = 0.0f;
  for (int i = 0; i < cs_vector<V>::lanes; ++i) sum += a.s[i] * b.s[i];
  return sum;
}
inline float3 cross(float3 a, float3 b) {
  return float3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class V, cs_if_vector<V> = 0> inline float length(V v) { return sqrtf(dot(v, v)); }
template <class V, cs_if_vector<V> = 0> inline V normalize(V v) { return v / length(v); }

/* select(a, b, c): b where c is true (scalar) or where its lane's top bit
 * is set (vector), else a. */
inline float select(float a, float b, int c) { return c ? b : a; }
inline uint select(uint a, uint b, int c) { return c ? b : a; }
template <class V, class M, cs_if_vector<V> = 0> inline V select(V a, V b, M c) {
  return cs_lanes<V>([&](int i) { return c.s[i] < 0 ? b.s[i] : a.s[i]; });
}
template <class M, cs_if_vector<M> = 0> inline int any(M m) {
  for (int i = 0; i < cs_vector<M>::lanes; ++i)
    if (m.s[i] < 0) return 1;
  return 0;
}
template <class M, cs_if_vector<M> = 0> inline int all(M m) {
  for (int i = 0; i < cs_vector<M>::lanes; ++i)
    if (m.s[i] >= 0) return 0;
  return 1;
}

/* as_T(v): the same bits read as T (sizes must match). */
template <class To, class From> inline To cs_bit_cast(From from) {
  static_assert(sizeof(To) == sizeof(From), "as_T: sizes differ");
  To to;
  std::memcpy(&to, &from, sizeof to);
  return to;
}
inline uint as_uint(float f) { return cs_bit_cast<uint>(f); }
inline int as_int(float f) { return cs_bit_cast<int>(f); }
inline float as_float(uint u) { return cs_bit_cast<float>(u); }
inline uint as_uint(char4 c) { return cs_bit_cast<uint>(c); }
inline ulong as_ulong(char8 c) { return cs_bit_cast<ulong>(c); }

/* convert_T(v): lane by lane, C's conversion (OpenCL's default rounding:
 * to nearest for float results, toward zero for integers). */
#define CS_CONVERT(T)                                                                          \
  template <class V, cs_if_vector<V> = 0> inline T convert_##T(V v) {                          \
    static_assert(cs_vector<V>::lanes == cs_vector<T>::lanes, "convert_" #T ": lane counts"); \
    return cs_lanes<T>([&](int i) { return cs_element<T>(v.s[i]); });                          \
  }
CS_CONVERT(float4)
CS_CONVERT(double4)
CS_CONVERT(int3)
CS_CONVERT(char4)
CS_CONVERT(char8)
#undef CS_CONVERT

/* shuffle(v, mask): lane i of the result is lane mask.s[i] of v. */
inline float4 shuffle(float4 v, uint4 mask) {
  return cs_lanes<float4>([&](int i) { return v.s[mask.s[i] & 3u]; });
}

/* vstoreN(v, offset, p): the lanes to p[N offset ...]. */
inline void vstore4(float4 v, size_t offset, float* p) {
  for (int i = 0; i < 4; ++i) p[4 * offset + i] = v.s[i];
}
inline void vstore8(float8 v, size_t offset, float* p) {
  for (int i = 0; i < 8; ++i) p[8 * offset + i] = v.s[i];
}

inline uint popcount(uint x) { return (uint)__builtin_popcount(x); }
inline ulong popcount(ulong x) { return (ulong)__builtin_popcountl(x); }
inline uint clz(uint x) { return x == 0u ? 32u : (uint)__builtin_clz(x); }
inline ulong clz(ulong x) { return x == 0ul ? 64ul : (ulong)__builtin_clzl(x); }

#endif /* __OPENCL_C_VERSION__ */

#endif /* CAUSTICA_SHARED_COMPAT_H */
