#!/bin/bash
# Which kernel layouts PoCL's work-group vectoriser turns into SIMD code, and
# what that is worth: builds layouts_bench.cpp, runs each kernel of
# layouts.cl in its own process (a fresh compile, so the vectoriser's
# remarks are that kernel's) and prints the loop vectoriser's verdict, the
# median time and a checksum (equal to about 1e-6 when the math agrees).
# Usage: bench/pocl_vectoriser/run.sh   (docs/performance.md has the figures)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
g++ -O2 -std=c++17 -o "$work/layouts_bench" "$here/layouts_bench.cpp" -lOpenCL -Wno-ignored-attributes
for kernel in step_float3 step_scalar_aos step_scalar_soa; do
  POCL_VECTORIZER_REMARKS=1 POCL_KERNEL_CACHE=0 "$work/layouts_bench" "$here/layouts.cl" "$kernel" \
    >"$work/out" 2>&1  # PoCL prints its remarks to stdout, unterminated
  verdict=$(tr '<' '\n' <"$work/out" | grep -oE "vectorized loop \(vectorization width: [0-9]+|loop not vectorized: [a-z ]+|Stores SLP vectorized" |
            sort -u | tr '\n' ';' || true)
  echo "$(grep -oE "step_[a-z0-9_]+ +median.*" "$work/out")  | ${verdict:-no loop remark}"
done
