#!/usr/bin/env bash
# The figures for the baked approach (docs/performance.md), each from one command whose full output lands in
# docs/profile/baked-<tag>/ (lavapipe on this project's machine unless --device says otherwise):
#   maps-*.md/csv     the blazed grating and the Xenopeltis scan at 256², FLSS at its defaults against baked
#                     (the Elaphe map is in scripts/readme-profile.sh's run, with every approach)
#   deep-*            the Elaphe scan at 4× its height (k·w·h up to 22): `terms`, then a 128² map profile
#   sphere-*          the smooth sphere under 65 µm coherence against a 4×4-sampled exact reference, 96²
#   scene-800.*       the default scene at 800²: GPU time of FLSS and baked (no reference: it would take hours)
#   view-800.txt      the viewer on the default scene at 800² under Xvfb (needs Xvfb)
#   table-cold.txt    the default scene's table built cold (empty cache), then loaded from the cache
# Usage: scripts/readme-baked.sh [TAG] [extra diffract options, e.g. --device 0]   (default tag: lavapipe)
source "$(dirname "$0")/lib/readme.sh"
out=docs/profile/baked-$tag
mkdir -p "$out"
afm=assets/afm

$d gen patch blazed --out "$scratch/blazed.gsf" >/dev/null
$d profile "$@" --heightfield "$scratch/blazed.gsf" --width 256 --exposure 3 --frames 3 --warmup 1 \
  --sweep approach=flss,baked --csv "$out/maps-blazed-256.csv" | tee "$out/maps-blazed-256.md"
$d profile "$@" --heightfield $afm/xenopeltis-100px.png --pixel-size-um 0.065 --height-um 0.44 --tile 10 \
  --width 256 --exposure 8 --frames 3 --warmup 1 --sweep approach=flss,baked \
  --csv "$out/maps-xenopeltis-256.csv" | tee "$out/maps-xenopeltis-256.md"

deep="--heightfield $afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 1.5 --tile 10"
# shellcheck disable=SC2086
$d terms $deep | tee "$out/deep-terms.txt"
# shellcheck disable=SC2086
$d profile "$@" $deep --width 128 --exposure 8 --frames 3 --warmup 1 --accept-f32-error \
  --sweep approach=flss,baked --csv "$out/deep-128.csv" | tee "$out/deep-128.md"

$d profile "$@" assets/scenes/elaphe-sphere.toml --width 96 --frames 3 --warmup 1 --reference-samples 4 \
  --sweep approach=flss,baked --csv "$out/sphere-96.csv" | tee "$out/sphere-96.md"
$d render "$@" assets/scenes/elaphe-sphere.toml --out "$out/sphere-flss.png" --width 256 --height 256 --approach flss
$d render "$@" assets/scenes/elaphe-sphere.toml --out "$out/sphere-baked.png" --width 256 --height 256 --approach baked

$d profile "$@" --width 800 --frames 3 --warmup 1 --no-reference --sweep approach=flss,baked \
  --csv "$out/scene-800.csv" | tee "$out/scene-800.md"

{
  echo "cold (empty cache):"
  DIFFRACT_CACHE="$scratch/cache" $d render "$@" --out "$scratch/a.png" --width 800 --height 800 2>&1
  echo "again (from the cache):"
  DIFFRACT_CACHE="$scratch/cache" $d render "$@" --out "$scratch/b.png" --width 800 --height 800 2>&1
} | tee "$out/table-cold.txt"

if command -v Xvfb >/dev/null; then
  start_xvfb 93
  $d view "$@" --width 800 --height 800 --frames 40 --vsync off | tail -1 | tee "$out/view-800.txt"
  kill "$xvfb"
fi
