#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang, AddressSanitizer and UBSan
# in build-fuzz/ and runs each for a bounded time from its committed seed
# corpus (fuzz/corpus/<target>), with our scenes, meshes and textures and,
# when ../shared exists, its files as extra seeds read where they lie (their
# licences forbid copying them into this repository). Fails on any finding:
# a crash, a sanitizer report, an exception other than caustica::Error, a
# timeout or running past the memory limit. The reproducer is left in
# $CAUSTICA_FUZZ_OUT (default build-fuzz/findings/); fix it, then make it a
# row of tests/test_cli_errors.cpp or a unit test next to the parser.
#   tools/fuzz.sh [seconds per target, default 60] [targets...]
# Two targets run at a time (CI machines have two cores). A fixed -seed makes
# a run explore the same inputs in the same order wherever it runs, so a
# slower machine explores a prefix of what a faster one did: CI does not
# fail on an input nobody has seen (new findings come from longer runs).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(fuzz_scene fuzz_obj fuzz_ply fuzz_texture fuzz_gltf fuzz_denoise_inputs fuzz_cli fuzz_state)
build="${CAUSTICA_FUZZ_BUILD_DIR:-$root/build-fuzz}"
out="${CAUSTICA_FUZZ_OUT:-$build/findings}"
shared="${CAUSTICA_SHARED_DIR:-$root/../shared}"

bash "$root/tools/setup.sh" --fuzz
if [[ ! -f $build/CMakeCache.txt ]]; then
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DCAUSTICA_FUZZ=ON -DCAUSTICA_BUILD_TESTS=OFF -DCAUSTICA_BUILD_BENCHMARKS=OFF -DCAUSTICA_PYTHON=OFF >&2
fi
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target "${targets[@]}" >&2

# Extra seeds from the repository and ../shared, by kind; small files only
# (inputs are cut to -max_len anyway).
seeds="$build/seeds"
rm -rf "$seeds"
mkdir -p "$seeds"/{fuzz_scene,fuzz_obj,fuzz_ply,fuzz_texture,fuzz_gltf,fuzz_denoise_inputs,fuzz_cli,fuzz_state} "$out"
collect() {  # collect TARGET DIR PATTERN...
  local target=$1 dir=$2
  shift 2
  [[ -d $dir ]] || return 0
  local args=()
  for p in "$@"; do args+=(-o -iname "$p"); done
  find "$dir" -type f -size -64k \( "${args[@]:1}" \) -print0 2>/dev/null |
    head -z -n 300 | while IFS= read -r -d '' f; do
      ln -sf "$f" "$seeds/$target/$(printf '%s' "$f" | md5sum | cut -c1-16)"
    done
}
collect fuzz_scene "$root/scenes" '*.json'
collect fuzz_obj "$root/scenes" '*.obj'
collect fuzz_texture "$root/textures" '*.png' '*.jpg'
collect fuzz_scene "$shared" '*.json'
collect fuzz_obj "$shared" '*.obj'
collect fuzz_ply "$shared" '*.ply'
collect fuzz_texture "$shared" '*.png' '*.jpg' '*.jpeg' '*.bmp' '*.tga' '*.ppm' '*.hdr'
collect fuzz_gltf "$root/scenes" '*.gltf' '*.glb'
collect fuzz_gltf "$shared" '*.gltf' '*.glb'

declare -A max_len=([fuzz_scene]=16384 [fuzz_obj]=8192 [fuzz_ply]=8192 [fuzz_texture]=4096 [fuzz_gltf]=16384
  [fuzz_denoise_inputs]=8192 [fuzz_cli]=2048 [fuzz_state]=65536)
# Debian's tinyexr 1.0.1 leaks part of an image whose load fails midway
# (LoadEXRImageFromMemory on a malformed chunk: ~60-byte blocks inside
# libtinyexr, whose other parts it has already freed, so freeing the image
# after the failure is a double free). Not ours to fix; everything else
# (crashes, sanitizer reports, exceptions, time and memory limits) is
# still a finding for that target. (LeakSanitizer also checks at exit, so
# both libFuzzer's flag and ASAN_OPTIONS say it.)
declare -A extra=([fuzz_denoise_inputs]="-detect_leaks=0")
declare -A asan=([fuzz_denoise_inputs]="detect_leaks=0")
run_one() {
  local t=$1
  local corpus="$build/corpus/$t"  # grows between runs; the committed corpus stays as it is
  mkdir -p "$corpus"
  local log="$out/$t.log"
  echo "[fuzz] $t: ${seconds}s" >&2
  if ASAN_OPTIONS="${ASAN_OPTIONS:-}${asan[$t]:+:${asan[$t]}}" "$build/fuzz/$t" "$corpus" "$root/fuzz/corpus/$t" "$seeds/$t" -max_total_time="$seconds" -seed=1 \
      -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2560 -print_final_stats=1 ${extra[$t]:-} \
      -artifact_prefix="$out/$t-" >"$log" 2>&1; then
    echo "[fuzz] $t: no findings ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') runs)" >&2
  else
    echo "[fuzz] $t: FINDING; log $log, reproducer:" $(ls "$out/$t-"* 2>/dev/null) >&2
    grep -m1 -A30 -E "ERROR: |runtime error|deadly signal|uncaught exception|Timeout|out-of-memory" "$log" >&2 || tail -30 "$log" >&2
    return 1
  fi
}

status=0
pids=()
for t in "${targets[@]}"; do
  run_one "$t" &
  pids+=($!)
  if ((${#pids[@]} == 2)); then
    wait "${pids[0]}" || status=1
    pids=("${pids[1]}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
