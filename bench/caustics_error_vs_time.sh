#!/usr/bin/env bash
# Error against time on scenes/caustics.json (64 x 48) for path tracing
# alone and with the photon pass, against the committed long path-traced
# reference; draws both on one plot (docs/caustics_error_vs_time.png) and
# prints the photon pass's share of render time (bench stage profile).
#   bench/caustics_error_vs_time.sh [SECONDS]   (default 60 each)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin="${CAUSTICA_BIN:-$root/build/caustica}"
seconds=${1:-60}
out=$(mktemp -d)
ref="$root/tests/references/caustics_pt_64x48.pfm"
common=(render "$root/scenes/caustics.json" --width 64 --height 48 --time "$seconds" --reference "$ref" -q)
"$bin" "${common[@]}" --caustics off --report "$out/path_tracing_alone.csv" -o "$out/alone.pfm"
"$bin" "${common[@]}" --caustics on --report "$out/with_photon_pass.csv" -o "$out/photons.pfm"
"$bin" plot "$out/path_tracing_alone.csv" "$out/with_photon_pass.csv" -o "$root/docs/caustics_error_vs_time.png"
for f in path_tracing_alone with_photon_pass; do echo "== $f"; grep -v '^#' "$out/$f.csv" | cut -d, -f1,2,5; done
"$bin" bench "$root/scenes/caustics.json" --mode path --spp 16 --repetitions 3
echo "reports in $out"
