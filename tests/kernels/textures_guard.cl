#line 2 "tests/kernels/textures_guard.cl"
/* tests/test_textures.cpp's Textures.LookupCompiledOnlyWithTheFlag: lib/
 * texture.h's body is guarded by HAS_TEXTURES, so without it a program may
 * define the same names itself. Only built, never run: what it checks is
 * the OpenCL compiler's view of the header. */
#include "lib/texture.h"
float3 texture_lookup(float x) { return (float3)(x); }
__kernel void k(__global float4* out) { out[0] = (float4)(texture_lookup(1.0f), 0.0f); }
