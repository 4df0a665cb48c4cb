#!/bin/bash
# What stops LLVM's loop vectoriser from running the path tracer's vertex
# (shade_path_vertex) eight paths at a time, with source locations: the
# SPIR route of run.sh (clang-15 -> SPIR -> scalarizer, builtins from
# spir_builtins.h) on kernels/, then PoCL's two optimisation steps
# emulated with opt-15 for skylake-avx512: -O3 on one work-item's vertex
# (SLP off), then the vertex inlined into a loop over paths and the loop
# vectoriser run on it. Prints the vectoriser's remarks for that loop
# (the first blocker it meets; fix it and run again).
# Usage: bench/pocl_vectoriser/vertex_remarks.sh [KERNEL_DIR]
#   FLAGS: the program's feature flags (default: the Cornell box's)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
kernels="${1:-$here/../../kernels}"
flags="${FLAGS:--DHAS_SPHERES=0 -DHAS_CYLINDERS=0 -DHAS_TRIANGLES=1 -DHAS_TRIANGLE_SHADING=0 -DHAS_TEXTURES=0
  -DHAS_LIGHTS=1 -DHAS_REFLECTION=0 -DHAS_REFRACTION=0 -DHAS_DIELECTRIC=0 -DHAS_AREA_LIGHTS=1 -DHAS_CAUSTICS=0
  -DHAS_NUMERIC_CHECKS=0 -DHAS_ENVIRONMENT=0}"
for tool in clang-15 opt-15 llvm-dis-15; do
  command -v $tool >/dev/null || { echo "vertex_remarks.sh: $tool not found (Debian: clang-15, llvm-15)" >&2; exit 1; }
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# shellcheck disable=SC2086
clang-15 -x cl -cl-std=CL1.2 -target spir64-unknown-unknown -g -Xclang -finclude-default-header \
  -D__OPENCL_VERSION__=300 -D__ENDIAN_LITTLE__=1 -include "$here/spir_builtins.h" -Dinline= -O1 \
  -fno-slp-vectorize -fno-vectorize -cl-fp32-correctly-rounded-divide-sqrt $flags -I "$kernels" \
  -Wno-ignored-pragmas -emit-llvm -c "$here/vertex_loop.cl" -o "$work/raw.bc"
opt-15 -passes='cgscc(inline),function(sroa,early-cse,instcombine,scalarizer,instcombine,dce),globaldce' \
  -inline-threshold=100000 -scalarize-load-store "$work/raw.bc" -o "$work/scalar.bc"
# PoCL retargets SPIR to the host: the same here, by hand.
llvm-dis-15 "$work/scalar.bc" -o - | sed -e 's/spir64-unknown-unknown/x86_64-pc-linux-gnu/' \
  -e 's/^target datalayout.*$//' -e 's/spir_func //g; s/spir_kernel //g' >"$work/x86.ll"
opt-15 -mtriple=x86_64-pc-linux-gnu -mcpu=skylake-avx512 -passes='default<O3>' -slp-threshold=1000000 \
  -vectorize-loops=false "$work/x86.ll" -S -o "$work/o3.ll"
sed -e 's/noinline//g' "$work/o3.ll" >"$work/loop.ll"
opt-15 -mtriple=x86_64-pc-linux-gnu -mcpu=skylake-avx512 -slp-threshold=1000000 -inline-threshold=100000 \
  -passes='cgscc(inline),function(sroa,instcombine,simplifycfg,loop-simplify,lcssa,loop(loop-rotate),loop-mssa(licm),loop-vectorize)' \
  -pass-remarks-output="$work/remarks.yaml" "$work/loop.ll" -S -o /dev/null
python3 - "$work/remarks.yaml" <<'PY'
import re, sys
for doc in open(sys.argv[1]).read().split('\n---'):
    if 'Function:        vertex_loop' not in doc or 'Pass:            loop-vectorize' not in doc:
        continue
    name = re.search(r'Name: +(\S+)', doc).group(1)
    loc = re.search(r"File: +'?([^',}]+)'?, Line: +(\d+)", doc)
    args = ''.join(re.findall(r"(?:String|VectorizationFactor|InterleaveCount): +'?([^'\n]*)'?", doc))
    print(f"{name:40s} {loc.group(1) + ':' + loc.group(2) if loc else '':55s} {args.strip()}")
PY
