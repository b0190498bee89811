#!/usr/bin/env bash
# Renders the BRDF maps of docs/approaches.md: a blazed grating and the two AFM snake patches (tiled to 65 µm), with each
# approach, at normal incidence, and prints the time each took (`diffract map` reports the GPU time).
# Usage: scripts/readme-maps.sh [OUT_DIR] [SIZE]   (default docs/images/maps, 256)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/images/maps}
size=${2:-256}
afm=assets/afm
mkdir -p "$out"
cargo build --release -q
$d gen patch blazed --out "$out/blazed.gsf" >/dev/null
# The snakes' orders are about 1 % of the specular peak: they need more exposure than the blazed grating.
declare -A exposure=([blazed]=3 [elaphe]=8 [xenopeltis]=8)
declare -A patch=(
  [blazed]="--heightfield $out/blazed.gsf"
  [elaphe]="--heightfield $afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 --tile 10"
  [xenopeltis]="--heightfield $afm/xenopeltis-100px.png --pixel-size-um 0.065 --height-um 0.44 --tile 10"
)
for name in blazed elaphe xenopeltis; do
  for approach in flss nmm pq gem; do
    start=$(date +%s%N)
    # shellcheck disable=SC2086
    line=$($d map ${patch[$name]} --light-theta 0 --approach "$approach" --size "$size" --exposure "${exposure[$name]}" \
      --out "$out/$name-$approach.png")
    end=$(date +%s%N)
    printf '%s %s wall %d ms: %s\n' "$name" "$approach" $(((end - start) / 1000000)) "$line"
  done
done
rm -f "$out/blazed.gsf"
montage "$out"/blazed-{flss,nmm,pq,gem}.png "$out"/elaphe-{flss,nmm,pq,gem}.png "$out"/xenopeltis-{flss,nmm,pq,gem}.png \
  -tile 4x3 -geometry +2+2 -background '#202020' "$out/grid.png"
