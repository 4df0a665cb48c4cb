#!/usr/bin/env bash
# Re-times the seed report's Table 1: 400 spheres and 1,600 / 6,400 / 12,800
# mixed spheres, cylinders and triangles, phong, 1200x800. The scenes are
# generated deterministically (caustica generate), so they need not be stored.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin="${CAUSTICA_BIN:-$root/build/caustica}"
out="${1:-$root/out/table1}"
mkdir -p "$out"
"$bin" generate --shapes 400 --spheres-only -o "$out/400_spheres.json"
for n in 1600 6400 12800; do
  "$bin" generate --shapes "$n" -o "$out/${n}_shapes.json"
done
for scene in 400_spheres 1600_shapes 6400_shapes 12800_shapes; do
  "$bin" bench "$out/$scene.json" --repetitions "${REPS:-5}" | tail -n 1
done
