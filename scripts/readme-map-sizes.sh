#!/usr/bin/env bash
# The "BRDF maps: baked against gem" figures of docs/performance.md: `diffract profile` of the Elaphe BRDF map
# (the AFM cut-out tiled to 65 µm, normal incidence) at 256² to 4096², gem against baked, each size's error
# measured against the exact reference at 2000 random pixels (the mean ΔE00 with its standard error).
# Writes docs/profile/elaphe-sizes-<tag>.csv and .md.
# Usage: scripts/readme-map-sizes.sh [TAG] [extra diffract options, e.g. --device 0]   (default tag: lavapipe)
source "$(dirname "$0")/lib/readme.sh"
mkdir -p docs/profile
target/release/diffract profile "$@" \
  --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \
  --exposure 8 --frames 5 --warmup 1 --roofline --reference-pixels 2000 \
  --sweep approach=gem,baked size=256,512,1024,2048,4096 \
  --csv "docs/profile/elaphe-sizes-$tag.csv" | tee "docs/profile/elaphe-sizes-$tag.md"
