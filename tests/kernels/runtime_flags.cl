#line 2 "tests/kernels/runtime_flags.cl"
/* tests/test_runtime.cpp's ProgramBuild.SameFlagsInAnotherOrderShareTheCacheEntry:
 * every feature flag has a value in every program (the unnamed ones their
 * defaults, kernels/shared/feature_flags.h); the kernel reports three. */
__kernel void k(__global int* x) { x[0] = HAS_SPHERES + 2 * HAS_TRIANGLES + 4 * HAS_DIELECTRIC; }
