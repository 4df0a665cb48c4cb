#line 2 "bench/pocl_vectoriser/layouts.cl"
/* One shade-like step (gather a normal and an albedo by primitive, turn the
 * normal toward the ray, cosine-sample a direction in its frame from a hash,
 * scale the throughput, rescale a dim one) written three ways, to see which
 * PoCL's work-group vectoriser turns into SIMD code. The math is the same
 * in all three; only the types and the record layout differ:
 *  - step_float3: float3 values, records as float4 arrays (how kernels/
 *    is written today);
 *  - step_scalar_aos: scalar floats only, records still float4 arrays read
 *    and written component by component;
 *  - step_scalar_soa: scalar floats only, each component its own array
 *    (x for every path, then y, then z);
 *  - step_float3_soa: float3 values, each component its own array (run.sh
 *    also builds it through SPIR and LLVM's scalarizer).
 * Sine and cosine are polynomials here in all four (PoCL's sin/cos call an
 * argument reduction it does not inline, which alone stops vectorisation). */

inline float poly_sin(float x) {
  const float x2 = x * x;
  return x * (1.0f + x2 * (-0.16666667f + x2 * (0.008333333f + x2 * -0.000198413f)));
}
inline float poly_cos(float x) {
  const float x2 = x * x;
  return 1.0f + x2 * (-0.5f + x2 * (0.041666667f + x2 * -0.001388889f));
}
inline uint mix32(uint h) {
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return h;
}

/* The float3 body, over loads and stores given as macros (float3 values,
 * float4 records or one array per component). */
#define FLOAT3_STEP(LOAD_DIR, LOAD_BETA, STORE_DIR, STORE_BETA)                                  \
  const uint i = get_global_id(0);                                                                \
  const uint p = prim[i];                                                                         \
  float3 nrm = normalize((float3)(normals[4 * p], normals[4 * p + 1], normals[4 * p + 2]));      \
  nrm = dot(nrm, LOAD_DIR()) > 0.0f ? -nrm : nrm;                                                 \
  const uint h = mix32(i * 0x9e3779b9u);                                                          \
  const float ux = (float)(h >> 8) * 0x1.0p-24f, uy = (float)(mix32(h) >> 8) * 0x1.0p-24f;        \
  const float r = sqrt(ux), phi = 6.2831853f * uy - 3.14159265f;                                  \
  const float z = sqrt(fmax(0.0f, 1.0f - ux));                                                    \
  float3 t = fabs(nrm.x) > 0.5f ? (float3)(0.0f, 1.0f, 0.0f) : (float3)(1.0f, 0.0f, 0.0f);        \
  const float3 b = normalize(cross(nrm, t));                                                      \
  t = cross(b, nrm);                                                                              \
  STORE_DIR(r * poly_cos(phi) * t + r * poly_sin(phi) * b + z * nrm);                             \
  const float3 beta = LOAD_BETA() * (float3)(albedo[4 * p], albedo[4 * p + 1], albedo[4 * p + 2]); \
  const float m = fmax(beta.x, fmax(beta.y, beta.z));                                             \
  STORE_BETA(m < 0.1f ? beta / fmax(2.0f * m, 1e-6f) : beta, m);

#define F4_LOAD_DIR() dir_in[i].xyz
#define F4_LOAD_BETA() throughput[i].xyz
#define F4_STORE_DIR(v) dir_out[i] = (float4)(v, 0.0f)
#define F4_STORE_BETA(v, w) throughput[i] = (float4)(v, w)
__kernel void step_float3(__global const float4* restrict dir_in, __global const uint* restrict prim,
                          __global const float* restrict normals, __global const float* restrict albedo,
                          __global float4* restrict dir_out, __global float4* restrict throughput, uint n) {
  FLOAT3_STEP(F4_LOAD_DIR, F4_LOAD_BETA, F4_STORE_DIR, F4_STORE_BETA)
}

/* The scalar body, over loads and stores given as macros. */
#define SCALAR_STEP(LOAD_DIR, LOAD_BETA, STORE_DIR, STORE_BETA)                                  \
  const uint i = get_global_id(0);                                                                \
  const uint p = prim[i];                                                                         \
  float nx = normals[4 * p], ny = normals[4 * p + 1], nz = normals[4 * p + 2];                    \
  const float inv = rsqrt(nx * nx + ny * ny + nz * nz);                                           \
  nx *= inv; ny *= inv; nz *= inv;                                                                \
  const float toward = nx * LOAD_DIR(0) + ny * LOAD_DIR(1) + nz * LOAD_DIR(2) > 0.0f ? -1.0f : 1.0f; \
  nx *= toward; ny *= toward; nz *= toward;                                                       \
  const uint h = mix32(i * 0x9e3779b9u);                                                          \
  const float ux = (float)(h >> 8) * 0x1.0p-24f, uy = (float)(mix32(h) >> 8) * 0x1.0p-24f;        \
  const float r = sqrt(ux), phi = 6.2831853f * uy - 3.14159265f;                                  \
  const float z = sqrt(fmax(0.0f, 1.0f - ux));                                                    \
  float tx = fabs(nx) > 0.5f ? 0.0f : 1.0f, ty = fabs(nx) > 0.5f ? 1.0f : 0.0f, tz = 0.0f;        \
  float bx = ny * tz - nz * ty, by = nz * tx - nx * tz, bz = nx * ty - ny * tx;                   \
  const float binv = rsqrt(bx * bx + by * by + bz * bz);                                          \
  bx *= binv; by *= binv; bz *= binv;                                                             \
  tx = by * nz - bz * ny; ty = bz * nx - bx * nz; tz = bx * ny - by * nx;                         \
  const float c = r * poly_cos(phi), s = r * poly_sin(phi);                                       \
  STORE_DIR(0, c * tx + s * bx + z * nx);                                                         \
  STORE_DIR(1, c * ty + s * by + z * ny);                                                         \
  STORE_DIR(2, c * tz + s * bz + z * nz);                                                         \
  STORE_DIR(3, 0.0f);                                                                             \
  const float b0 = LOAD_BETA(0) * albedo[4 * p], b1 = LOAD_BETA(1) * albedo[4 * p + 1],           \
              b2 = LOAD_BETA(2) * albedo[4 * p + 2];                                              \
  const float m = fmax(b0, fmax(b1, b2));                                                         \
  const float scale = m < 0.1f ? 1.0f / fmax(2.0f * m, 1e-6f) : 1.0f;                             \
  STORE_BETA(0, b0 * scale);                                                                      \
  STORE_BETA(1, b1 * scale);                                                                      \
  STORE_BETA(2, b2 * scale);                                                                      \
  STORE_BETA(3, m);

#define AOS_LOAD_DIR(k) dir_in[4 * i + (k)]
#define AOS_LOAD_BETA(k) throughput[4 * i + (k)]
#define AOS_STORE_DIR(k, v) dir_out[4 * i + (k)] = (v)
#define AOS_STORE_BETA(k, v) throughput[4 * i + (k)] = (v)
__kernel void step_scalar_aos(__global const float* restrict dir_in, __global const uint* restrict prim,
                              __global const float* restrict normals, __global const float* restrict albedo,
                              __global float* restrict dir_out, __global float* restrict throughput, uint n) {
  SCALAR_STEP(AOS_LOAD_DIR, AOS_LOAD_BETA, AOS_STORE_DIR, AOS_STORE_BETA)
}

#define SOA_LOAD_DIR(k) dir_in[(k) * n + i]
#define SOA_LOAD_BETA(k) throughput[(k) * n + i]
#define SOA_STORE_DIR(k, v) dir_out[(k) * n + i] = (v)
#define SOA_STORE_BETA(k, v) throughput[(k) * n + i] = (v)
__kernel void step_scalar_soa(__global const float* restrict dir_in, __global const uint* restrict prim,
                              __global const float* restrict normals, __global const float* restrict albedo,
                              __global float* restrict dir_out, __global float* restrict throughput, uint n) {
  SCALAR_STEP(SOA_LOAD_DIR, SOA_LOAD_BETA, SOA_STORE_DIR, SOA_STORE_BETA)
}

/* float3 values as in step_float3, records one array per component. PoCL
 * does not vectorise it from source (the float3 arithmetic is vector IR);
 * run.sh also compiles it to SPIR, splits the vectors with LLVM's
 * scalarizer and loads that binary, which PoCL does vectorise. */
#define F3_SOA_LOAD_DIR() (float3)(dir_in[i], dir_in[n + i], dir_in[2 * n + i])
#define F3_SOA_LOAD_BETA() (float3)(throughput[i], throughput[n + i], throughput[2 * n + i])
#define F3_SOA_STORE_DIR(v) \
  do {                      \
    const float3 d_ = (v);  \
    dir_out[i] = d_.x;      \
    dir_out[n + i] = d_.y;  \
    dir_out[2 * n + i] = d_.z; \
    dir_out[3 * n + i] = 0.0f; \
  } while (0)
#define F3_SOA_STORE_BETA(v, w)   \
  do {                            \
    const float3 b_ = (v);        \
    throughput[i] = b_.x;         \
    throughput[n + i] = b_.y;     \
    throughput[2 * n + i] = b_.z; \
    throughput[3 * n + i] = (w);  \
  } while (0)
__kernel void step_float3_soa(__global const float* restrict dir_in, __global const uint* restrict prim,
                              __global const float* restrict normals, __global const float* restrict albedo,
                              __global float* restrict dir_out, __global float* restrict throughput, uint n) {
  FLOAT3_STEP(F3_SOA_LOAD_DIR, F3_SOA_LOAD_BETA, F3_SOA_STORE_DIR, F3_SOA_STORE_BETA)
}
