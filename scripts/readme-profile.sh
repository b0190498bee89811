#!/usr/bin/env bash
# The "Performance and accuracy" figures of docs/performance.md: `diffract profile` of the Elaphe BRDF map (the AFM cut-out
# tiled to 65 µm, normal incidence) at 256², across the five approaches, Taylor orders and wavelength steps,
# with the roofline probe. Writes docs/profile/elaphe-256-<tag>.csv and docs/images/profile-elaphe-<tag>.png.
# Usage: scripts/readme-profile.sh [TAG] [extra diffract options, e.g. --device 0]   (default tag: lavapipe)
source "$(dirname "$0")/lib/readme.sh"
mkdir -p docs/profile docs/images
target/release/diffract profile "$@" \
  --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \
  --width 256 --exposure 8 --frames 3 --warmup 1 --roofline \
  --sweep approach=flss,nmm,pq,gem,baked --sweep order=2,4,8,16 --sweep lambda_step_nm=1,2,10,20 \
  --csv "docs/profile/elaphe-256-$tag.csv" --plot "docs/images/profile-elaphe-$tag.png" \
  | tee "docs/profile/elaphe-256-$tag.md"
