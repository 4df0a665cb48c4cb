#line 2 "tests/kernels/runtime_cached.cl"
/* tests/test_runtime.cpp's ProgramBuild.SecondBuildComesFromTheCache: a
 * trivial kernel, built cold, then from the on-disk program cache, and run
 * to show that the cached binary works. */
__kernel void k(__global int* x) { x[get_global_id(0)] = 7; }
