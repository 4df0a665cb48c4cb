#!/usr/bin/env bash
# caustica vs Embree on the same scenes and the same rays (README,
# "Benchmarks"). Runs `caustica bench` and `caustica_embree_bench` one after
# the other for each scene, PASSES times over, swapping which goes first on
# every pass, so that background load and thermal drift hit both alike; then
# prints a markdown table of per-tool medians over the passes and their
# ratios. Both tools use THREADS threads (PoCL: POCL_MAX_PTHREAD_COUNT).
#
#   bench/run_embree_comparison.sh [OUT_DIR]
#   env: PASSES (2), THREADS (2), REPS (5), SCENES (the three bench/scenes),
#        CAUSTICA_BUILD (build-bench), CAUSTICA_BIN, EMBREE_BIN
# Each pass also times the fast builds, `caustica bench --bvh fast` against
# Embree's default (medium quality) build, with one repetition of the rays.
# The raw JSON lines stay in OUT_DIR (default out/embree_comparison).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="${CAUSTICA_BUILD:-$root/build-bench}"
caustica="${CAUSTICA_BIN:-$build/caustica}"
embree="${EMBREE_BIN:-$build/caustica_embree_bench}"
passes="${PASSES:-2}"
threads="${THREADS:-2}"
reps="${REPS:-5}"
read -r -a scenes <<< "${SCENES:-bunny_front sponza_inside conference_inside}"
out="${1:-$root/out/embree_comparison}"

for bin in "$caustica" "$embree"; do
  if [[ ! -x "$bin" ]]; then
    echo "run_embree_comparison.sh: $bin not found; build it with" >&2
    echo "  cmake -S $root -B $build -DCMAKE_BUILD_TYPE=Release -DCAUSTICA_EMBREE_REFERENCE=ON" >&2
    echo "  cmake --build $build -j2 --target caustica caustica_embree_bench" >&2
    exit 1
  fi
done
if (( passes < 2 )); then echo "run_embree_comparison.sh: PASSES must be >= 2" >&2; exit 1; fi

mkdir -p "$out"
for scene in "${scenes[@]}"; do
  : > "$out/$scene.caustica.jsonl"
  : > "$out/$scene.embree.jsonl"
  : > "$out/$scene.caustica_fast.jsonl"
  : > "$out/$scene.embree_medium.jsonl"
done

export POCL_MAX_PTHREAD_COUNT="$threads"
run_caustica() {
  echo "  caustica bench        $1" >&2
  "$caustica" bench "$root/bench/scenes/$1.json" --repetitions "$reps" | tail -n 1 >> "$out/$1.caustica.jsonl"
}
run_embree() {
  echo "  caustica_embree_bench $1" >&2
  "$embree" "$root/bench/scenes/$1.json" --repetitions "$reps" --threads "$threads" | tail -n 1 \
    >> "$out/$1.embree.jsonl"
}

run_fast_builds() {
  echo "  caustica bench --bvh fast / caustica_embree_bench --build medium  $1" >&2
  "$caustica" bench "$root/bench/scenes/$1.json" --repetitions 1 --bvh fast | tail -n 1 \
    >> "$out/$1.caustica_fast.jsonl"
  "$embree" "$root/bench/scenes/$1.json" --repetitions 1 --threads "$threads" --build medium | tail -n 1 \
    >> "$out/$1.embree_medium.jsonl"
}

for ((pass = 1; pass <= passes; ++pass)); do
  echo "pass $pass of $passes" >&2
  for scene in "${scenes[@]}"; do
    if (( pass % 2 == 1 )); then
      run_caustica "$scene"
      run_embree "$scene"
    else
      run_embree "$scene"
      run_caustica "$scene"
    fi
    run_fast_builds "$scene"
  done
done

python3 - "$out" "$threads" "$passes" "${scenes[@]}" <<'EOF'
import json, statistics, sys

out, threads, passes, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]

def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]

def median(runs, key):
    values = [r[key] for r in runs if key in r]
    return statistics.median(values) if values else float("nan")

# caustica's build time is the binary SBVH plus its collapse to the wide
# layout the kernels use: the time until tracing can start, like Embree's.
def with_collapse(runs):
    for r in runs:
        r["total_build_ms"] = r.get("build_ms", 0.0) + r.get("collapse_ms", 0.0)
    return runs

rows = [("primary_mrays", "primary Mrays/s", True), ("diffuse_mrays", "diffuse Mrays/s", True),
        ("shadow_mrays", "shadow Mrays/s", True), ("total_build_ms", "BVH build ms (high quality)", False),
        ("fast_build_ms", "BVH build ms (fast / Embree default)", False)]
print(f"caustica (OpenCL, PoCL, {threads} threads) vs Embree (rtcIntersect1/rtcOccluded1, {threads} threads): "
      f"medians of {passes} interleaved passes\n")
print("| scene | measure | caustica | Embree | caustica / Embree |")
print("|---|---|---:|---:|---:|")
notes = []
for scene in scenes:
    c, e = with_collapse(load(f"{out}/{scene}.caustica.jsonl")), load(f"{out}/{scene}.embree.jsonl")
    for r in e:
        r["total_build_ms"] = r["build_ms"]
    fast_c = with_collapse(load(f"{out}/{scene}.caustica_fast.jsonl"))
    fast_e = load(f"{out}/{scene}.embree_medium.jsonl")
    c[0]["fast_build_ms"] = median(fast_c, "total_build_ms")
    e[0]["fast_build_ms"] = median(fast_e, "build_ms")
    label = f"{scene} ({c[0]['triangles']:,} tris, {c[0]['width']}x{c[0]['height']})"
    for key, name, _ in rows:
        cv, ev = median(c, key), median(e, key)
        ratio = cv / ev if ev > 0 else float("nan")
        print(f"| {label} | {name} | {cv:.2f} | {ev:.2f} | {ratio:.2f} |")
        label = ""
    for kind in ("primary", "diffuse", "shadow"):
        agree = min(min(r.get(f"{kind}_agreement", 1.0) for r in c), min(r.get(f"{kind}_agreement", 1.0) for r in e))
        if agree < 0.999:
            notes.append(f"{scene} {kind}: hit/miss agreement with the host trace only {100 * agree:.4f}%")
print()
print("Mrays/s: higher is better, so a ratio below 1 means caustica is slower; build ms: lower is better.")
print("caustica build ms = binary BVH (SBVH, or --bvh fast) + collapse to the 8-wide layout; Embree: rtcCommitScene "
      "at build quality high, or medium (its default) in the fast row.")
for n in notes:
    print(f"WARNING: {n}")
EOF
