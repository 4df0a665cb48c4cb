#!/usr/bin/env bash
# What denoising a 1920x1080 image costs on this machine (issue 37's target:
# at most 1.5 s on the CPU), against OIDN's own benchmark as the baseline.
#   bench/denoise_benchmark.sh [threads, default 2] [repetitions, default 3]
# 1. renders scenes/showcase_path.json at 1920x1080, 4 spp, to an EXR with
#    its aux layers (the render's time is not what is measured);
# 2. times `caustica denoise` on it (the filter's own seconds, as the
#    command prints them: buffers, filter creation and execution; the EXR's
#    reading and writing left out), each quality, with clean guides and with
#    --noisy-guides (the guides denoised first: three filter runs);
# 3. runs OIDN's oidnBenchmark from the same pinned wheel (pip download into
#    a temporary folder) on RT.hdr_calb_cnrm.1920x1080 and RT.hdr_alb_nrm.1920x1080.
# Run it on a quiet machine: every number is wall time.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
threads=${1:-2}
reps=${2:-3}
caustica="${CAUSTICA_BINARY:-$root/build/caustica}"
lib="$root/.deps/oidn-2.5.1/lib"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $threads threads"
POCL_MAX_PTHREAD_COUNT=$threads "$caustica" render "$root/scenes/showcase_path.json" --width 1920 --height 1080 \
  --spp 4 --no-adaptive -q -o "$tmp/in.exr"
for quality in high balanced fast; do
  for guides in "" --noisy-guides; do
    for ((i = 0; i < reps; i++)); do
      "$caustica" denoise "$tmp/in.exr" -o "$tmp/out.exr" --threads "$threads" --quality $quality $guides 2>&1 |
        sed -n 's/.* in \([0-9.]*\) s: wrote.*/\1/p'
    done | sort -n | awk -v q=$quality -v g="${guides:-clean guides}" '{t[NR]=$1} END {printf "caustica denoise 1920x1080 %s, %s: median %.3f s (min %.3f, max %.3f)\n", q, g, t[int((NR+1)/2)], t[1], t[NR]}'
  done
done
if python3 -m pip download --quiet --no-deps --only-binary=:all: -d "$tmp" pyoidn==2.5.1.0 >/dev/null 2>&1; then
  python3 -c "import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extract('pyoidn/oidn/bin/oidnBenchmark', sys.argv[2])" \
    "$tmp"/pyoidn-2.5.1.0-*.whl "$tmp"
  bench="$tmp/pyoidn/oidn/bin/oidnBenchmark"
  chmod +x "$bench"
  for run in RT.hdr_calb_cnrm.1920x1080 RT.hdr_alb_nrm.1920x1080; do
    LD_LIBRARY_PATH="$lib" "$bench" -d cpu --threads "$threads" -r "$run" -n "$reps" 2>&1 | grep -E "^RT" || true
  done
else
  echo "oidnBenchmark: pip could not fetch pyoidn==2.5.1.0 (offline?)"
fi
