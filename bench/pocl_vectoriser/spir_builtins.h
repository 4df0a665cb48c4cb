/* For the SPIR route of run.sh and vertex_remarks.sh (bench only): the
 * OpenCL builtins the kernels call on vectors, written component by
 * component and always inlined, so that LLVM's scalarizer can split every
 * float3 value. PoCL's own builtins arrive after the scalarizer (it links
 * them into the SPIR program) and would bring vector code back. Scalar
 * sqrt / fabs / fmin / fmax / floor / fma / copysign become LLVM intrinsics,
 * which the loop vectoriser widens. float8 and double keep the builtins.
 * Included before the kernel source (clang -include). */
#define CS_OVL __attribute__((overloadable, always_inline))
CS_OVL float cs_dot(float2 a, float2 b) { return a.x * b.x + a.y * b.y; }
CS_OVL float cs_dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
CS_OVL float cs_dot(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
CS_OVL float3 cs_cross(float3 a, float3 b) { return (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
CS_OVL float cs_sqrt(float x) { return __builtin_sqrtf(x); }
CS_OVL float3 cs_sqrt(float3 x) { return (float3)(__builtin_sqrtf(x.x), __builtin_sqrtf(x.y), __builtin_sqrtf(x.z)); }
CS_OVL float cs_fabs(float x) { return __builtin_fabsf(x); }
CS_OVL float2 cs_fabs(float2 x) { return (float2)(__builtin_fabsf(x.x), __builtin_fabsf(x.y)); }
CS_OVL float3 cs_fabs(float3 x) { return (float3)(__builtin_fabsf(x.x), __builtin_fabsf(x.y), __builtin_fabsf(x.z)); }
CS_OVL float4 cs_fabs(float4 x) { return (float4)(__builtin_fabsf(x.x), __builtin_fabsf(x.y), __builtin_fabsf(x.z), __builtin_fabsf(x.w)); }
CS_OVL float cs_fmax(float a, float b) { return __builtin_fmaxf(a, b); }
CS_OVL float3 cs_fmax(float3 a, float3 b) { return (float3)(__builtin_fmaxf(a.x, b.x), __builtin_fmaxf(a.y, b.y), __builtin_fmaxf(a.z, b.z)); }
CS_OVL float3 cs_fmax(float3 a, float b) { return cs_fmax(a, (float3)(b)); }
CS_OVL float4 cs_fmax(float4 a, float4 b) { return (float4)(__builtin_fmaxf(a.x, b.x), __builtin_fmaxf(a.y, b.y), __builtin_fmaxf(a.z, b.z), __builtin_fmaxf(a.w, b.w)); }
CS_OVL float cs_fmin(float a, float b) { return __builtin_fminf(a, b); }
CS_OVL float3 cs_fmin(float3 a, float3 b) { return (float3)(__builtin_fminf(a.x, b.x), __builtin_fminf(a.y, b.y), __builtin_fminf(a.z, b.z)); }
CS_OVL float3 cs_fmin(float3 a, float b) { return cs_fmin(a, (float3)(b)); }
CS_OVL float4 cs_fmin(float4 a, float4 b) { return (float4)(__builtin_fminf(a.x, b.x), __builtin_fminf(a.y, b.y), __builtin_fminf(a.z, b.z), __builtin_fminf(a.w, b.w)); }
CS_OVL float cs_clamp(float x, float lo, float hi) { return __builtin_fminf(__builtin_fmaxf(x, lo), hi); }
CS_OVL float3 cs_clamp(float3 x, float lo, float hi) { return cs_fmin(cs_fmax(x, lo), hi); }
CS_OVL float3 cs_clamp(float3 x, float3 lo, float3 hi) { return cs_fmin(cs_fmax(x, lo), hi); }
CS_OVL float cs_floor(float x) { return __builtin_floorf(x); }
CS_OVL float cs_fma(float a, float b, float c) { return __builtin_fmaf(a, b, c); }
CS_OVL float3 cs_fma(float3 a, float3 b, float3 c) { return (float3)(__builtin_fmaf(a.x, b.x, c.x), __builtin_fmaf(a.y, b.y, c.y), __builtin_fmaf(a.z, b.z, c.z)); }
CS_OVL float cs_copysign(float a, float b) { return __builtin_copysignf(a, b); }
CS_OVL float3 cs_copysign(float3 a, float3 b) { return (float3)(__builtin_copysignf(a.x, b.x), __builtin_copysignf(a.y, b.y), __builtin_copysignf(a.z, b.z)); }
CS_OVL float cs_length(float3 v) { return __builtin_sqrtf(cs_dot(v, v)); }
CS_OVL float cs_length(float2 v) { return __builtin_sqrtf(cs_dot(v, v)); }
CS_OVL float3 cs_normalize(float3 v) { return v * (1.0f / __builtin_sqrtf(cs_dot(v, v))); }
CS_OVL float cs_rsqrt(float x) { return 1.0f / __builtin_sqrtf(x); }
CS_OVL float cs_mix(float a, float b, float t) { return a + (b - a) * t; }
CS_OVL float3 cs_mix(float3 a, float3 b, float t) { return a + (b - a) * t; }
CS_OVL float3 cs_mix(float3 a, float3 b, float3 t) { return a + (b - a) * t; }
CS_OVL float8 cs_fma(float8 a, float8 b, float8 c) { return fma(a, b, c); }
CS_OVL float8 cs_fmin(float8 a, float8 b) { return fmin(a, b); }
CS_OVL float8 cs_fmax(float8 a, float8 b) { return fmax(a, b); }
CS_OVL float2 cs_fmin(float2 a, float2 b) { return fmin(a, b); }
CS_OVL float2 cs_fmax(float2 a, float2 b) { return fmax(a, b); }
CS_OVL float2 cs_floor(float2 a) { return floor(a); }
CS_OVL float4 cs_floor(float4 a) { return floor(a); }
CS_OVL float3 cs_floor(float3 a) { return floor(a); }
CS_OVL float4 cs_sqrt(float4 a) { return sqrt(a); }
CS_OVL float4 cs_fma(float4 a, float4 b, float4 c) { return fma(a, b, c); }
CS_OVL float4 cs_mix(float4 a, float4 b, float t) { return mix(a, b, t); }
CS_OVL float4 cs_clamp(float4 x, float lo, float hi) { return clamp(x, lo, hi); }
CS_OVL float2 cs_clamp(float2 x, float lo, float hi) { return clamp(x, lo, hi); }
CS_OVL int cs_clamp(int x, int lo, int hi) { return clamp(x, lo, hi); }
CS_OVL uint cs_clamp(uint x, uint lo, uint hi) { return clamp(x, lo, hi); }
CS_OVL double cs_fma(double a, double b, double c) { return fma(a, b, c); }
CS_OVL double cs_fabs(double a) { return fabs(a); }
CS_OVL double cs_sqrt(double a) { return sqrt(a); }
CS_OVL double cs_floor(double a) { return floor(a); }
CS_OVL double cs_fmin(double a, double b) { return fmin(a, b); }
CS_OVL double cs_fmax(double a, double b) { return fmax(a, b); }
#define dot cs_dot
#define cross cs_cross
#define sqrt cs_sqrt
#define fabs cs_fabs
#define fmax cs_fmax
#define fmin cs_fmin
#define clamp cs_clamp
#define floor cs_floor
#define fma cs_fma
#define copysign cs_copysign
#define length cs_length
#define normalize cs_normalize
#define rsqrt cs_rsqrt
#define mix cs_mix
