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
# box's is tests/references/cornell_box_128_8192spp.pfm). relMSE x spp and
# relMSE x s (s: the `-v` render time, kernels already built) are means
# over two seeds; adaptive sampling is off, so that each image has its spp
# in every pixel. Timings want an otherwise idle machine. The Markdown
# table goes to stdout.
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

render() {  # scene w h spp seed out [extra kernel options]; prints the render's seconds
  CAUSTICA_EXTRA_KERNEL_OPTIONS="${7:-}" "$bin" render "$1" --mode path --width "$2" --height "$3" --spp "$4" \
    --seed "$5" --no-adaptive --exposure 0 -v -o "$6" 2>&1 | sed -n 's/.*render: \([0-9.]*\) ms.*/\1/p' |
    awk '{print $1 / 1000}'
}
relmse() { "$bin" diff "$1" "$2" | sed -n 's/^relMSE *\([0-9.e+-]*\).*/\1/p'; }

echo "| scene | size | sampling | relMSE x spp ($spp spp, 2 seeds) | vs area | relMSE x s | vs area |"
echo "|---|---|---|---:|---:|---:|---:|"
for entry in "${scenes[@]}"; do
  read -r name file w h <<<"$entry"
  if [ "$name" = cornell_box ]; then
    ref=tests/references/cornell_box_128_8192spp.pfm
  else
    ref=$cache/$name-$(sha1sum "$file" | cut -c1-8)-${w}x$h-4096spp.pfm
    [ -f "$ref" ] || { echo "reference $ref ..." >&2; render "$file" "$w" "$h" 4096 7 "$ref" >/dev/null; }
  fi
  score() {  # extra options -> "relMSE x spp  relMSE x s", means over seeds 1, 2
    local spp_sum=0 s_sum=0
    render "$file" "$w" "$h" 1 1 "$tmp/img.pfm" "$1" >/dev/null  # builds the kernels, untimed
    for seed in 1 2; do
      local seconds err
      seconds=$(render "$file" "$w" "$h" "$spp" "$seed" "$tmp/img.pfm" "$1")
      err=$(relmse "$tmp/img.pfm" "$ref")
      spp_sum=$(python3 -c "print($spp_sum + $err * $spp / 2)")
      s_sum=$(python3 -c "print($s_sum + $err * $seconds / 2)")
    done
    echo "$spp_sum $s_sum"
  }
  read -r area area_s <<<"$(score "-DLIGHT_SPHERICAL_MIN_SOLID_ANGLE=1e30f")"
  printf "| %s | %sx%s | area | %.4g | 1 | %.4g | 1 |\n" "$name" "$w" "$h" "$area" "$area_s"
  for t in "${thresholds[@]}"; do
    opt=""
    label="solid angle (built-in threshold)"
    if [ "$t" != default ]; then opt="-DLIGHT_SPHERICAL_MIN_SOLID_ANGLE=${t}f"; label="solid angle above $t sr"; fi
    read -r v vs <<<"$(score "$opt")"
    printf "| %s | %sx%s | %s | %.4g | %.3f | %.4g | %.3f |\n" "$name" "$w" "$h" "$label" "$v" \
      "$(python3 -c "print($v / $area)")" "$vs" "$(python3 -c "print($vs / $area_s)")"
  done
done
