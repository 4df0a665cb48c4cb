#!/usr/bin/env bash
# relMSE x spp of next-event estimation toward planar lights sampled by the
# solid angle they subtend (spherical rectangles and triangles, issue 39)
# against sampling them by area, at the same spp and seeds (optional; not
# part of the tests or CI).
#
#   bench/light_sampling_variance.sh [SPP] [THRESHOLDS...]
#
# "area" is the same build with LIGHT_SPHERICAL_MIN_SOLID_ANGLE (the
# solid angle above which a light is sampled by solid angle,
# kernels/lib/spherical_sampling.h) set beyond any light through
# CAUSTICA_EXTRA_KERNEL_OPTIONS; each THRESHOLD (steradians, default: the
# built-in one) is a row of its own. Each scene's reference is a 4096-spp
# render of this build, cached in bench/light_sampling/cache (the Cornell
# box's is tests/references/cornell_box_128_8192spp.pfm). relMSE x spp is
# the mean over two seeds; adaptive sampling is off, so that each image has
# its spp in every pixel. The Markdown table goes to stdout.
set -euo pipefail
cd "$(dirname "$0")/.."
spp=${1:-64}
shift || true
thresholds=("$@")
[ ${#thresholds[@]} -eq 0 ] && thresholds=(default)
bin=build/caustica
cache=bench/light_sampling/cache
mkdir -p "$cache"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

scenes=(
  "cornell_box scenes/cornell_box.json 128 128"
  "caustics scenes/caustics.json 160 120"
  "showcase_path scenes/showcase_path.json 160 90"
  "large_light_wall bench/scenes/large_light_wall.json 192 128"
)

render() {  # scene w h spp seed out [extra kernel options]
  CAUSTICA_EXTRA_KERNEL_OPTIONS="${7:-}" "$bin" render "$1" --mode path --width "$2" --height "$3" --spp "$4" \
    --seed "$5" --no-adaptive --exposure 0 -q -o "$6"
}
relmse() { "$bin" diff "$1" "$2" | sed -n 's/^relMSE *\([0-9.e+-]*\).*/\1/p'; }

echo "| scene | size | sampling | relMSE x spp ($spp spp, 2 seeds) | vs area |"
echo "|---|---|---|---:|---:|"
for entry in "${scenes[@]}"; do
  read -r name file w h <<<"$entry"
  if [ "$name" = cornell_box ]; then
    ref=tests/references/cornell_box_128_8192spp.pfm
  else
    ref=$cache/$name-$(sha1sum "$file" | cut -c1-8)-${w}x$h-4096spp.pfm
    [ -f "$ref" ] || { echo "reference $ref ..." >&2; render "$file" "$w" "$h" 4096 7 "$ref"; }
  fi
  score() {  # extra options -> mean relMSE x spp over seeds 1, 2
    local sum=0
    for seed in 1 2; do
      render "$file" "$w" "$h" "$spp" "$seed" "$tmp/img.pfm" "$1"
      sum=$(python3 -c "print($sum + $(relmse "$tmp/img.pfm" "$ref") * $spp / 2)")
    done
    echo "$sum"
  }
  area=$(score "-DLIGHT_SPHERICAL_MIN_SOLID_ANGLE=1e30f")
  printf "| %s | %sx%s | area | %.4g | 1 |\n" "$name" "$w" "$h" "$area"
  for t in "${thresholds[@]}"; do
    opt=""
    label="solid angle (built-in threshold)"
    if [ "$t" != default ]; then opt="-DLIGHT_SPHERICAL_MIN_SOLID_ANGLE=${t}f"; label="solid angle above $t sr"; fi
    s=$(score "$opt")
    printf "| %s | %sx%s | %s | %.4g | %.3f |\n" "$name" "$w" "$h" "$label" "$s" "$(python3 -c "print($s / $area)")"
  done
done
