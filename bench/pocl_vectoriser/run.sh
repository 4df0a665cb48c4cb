#!/bin/bash
# Which kernel layouts PoCL's work-group vectoriser turns into SIMD code, and
# what that is worth: builds layouts_bench.cpp, runs each kernel of
# layouts.cl in its own process (a fresh compile, so the vectoriser's
# remarks are that kernel's) and prints the loop vectoriser's verdict, the
# median time and a checksum (equal to about 1e-6 when the math agrees).
# With clang-15 and opt-15 (Debian's clang-15 and llvm-15) it also builds
# the float3 kernels the SPIR way: clang -> SPIR bitcode -> LLVM's
# scalarizer -> clCreateProgramWithBinary, PoCL's SLP vectoriser off.
# Usage: bench/pocl_vectoriser/run.sh   (docs/performance.md has the figures)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
g++ -O2 -std=c++17 -o "$work/layouts_bench" "$here/layouts_bench.cpp" -lOpenCL -ldl -Wno-ignored-attributes

run() {  # run LABEL PROGRAM KERNEL [env...]
  local label=$1 program=$2 kernel=$3
  shift 3
  env "$@" POCL_VECTORIZER_REMARKS=1 POCL_KERNEL_CACHE=0 "$work/layouts_bench" "$program" "$kernel" \
    >"$work/out" 2>&1  # PoCL prints its remarks to stdout, unterminated
  verdict=$(tr '<' '\n' <"$work/out" | grep -oE "vectorized loop \(vectorization width: [0-9]+|loop not vectorized: [a-z ]+|Stores SLP vectorized" |
            sort -u | tr '\n' ';' || true)
  printf '%-7s %s  | %s\n' "$label" "$(grep -oE "step_[a-z0-9_]+ +median.*" "$work/out")" "${verdict:-no loop remark}"
}

for kernel in step_float3 step_scalar_aos step_scalar_soa step_float3_soa; do
  run source "$here/layouts.cl" "$kernel"
done

if command -v clang-15 >/dev/null && command -v opt-15 >/dev/null; then
  # -Dinline=: OpenCL C 1.2's inline has C99's meaning (no external
  # definition), and a SPIR program must define what it calls.
  clang-15 -x cl -cl-std=CL1.2 -target spir64-unknown-unknown -Xclang -finclude-default-header \
    -include "$here/spir_builtins.h" -Dinline= -O1 -fno-slp-vectorize -fno-vectorize \
    -emit-llvm -c "$here/layouts.cl" -o "$work/layouts.raw.bc"
  opt-15 -passes='function(scalarizer,instcombine,dce)' -scalarize-load-store "$work/layouts.raw.bc" -o "$work/layouts.bc"
  for kernel in step_float3 step_float3_soa; do
    run spir "$work/layouts.bc" "$kernel" LLVM_OPTION=-slp-threshold=1000000
  done
else
  echo "(clang-15 / opt-15 not found: the SPIR rows need Debian's clang-15 and llvm-15)"
fi
