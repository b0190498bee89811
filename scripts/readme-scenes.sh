#!/usr/bin/env bash
# The pictures of scenes (README and docs/usage.md), each from the diffract command its caption names (lavapipe on this project's
# machine unless extra options, e.g. --device 0, say otherwise); the commands' output lands in
# docs/profile/scenes-<tag>.txt:
#   docs/images/snake.png            the default scene (the snake under the clear sky) at 800² (the README's first image)
#   docs/images/snake-annotated.png  the same frame, with the approach named and the material's BRDF map inset
#   docs/images/scenes.png           the four shipped scenes in the thesis's relative units (the sun alone) at 320², their
#                                    tables built from an empty cache
#   docs/images/light-sweep.png      the default scene at 240² as the light turns through 50° (6 frames)
#   docs/images/view.png             the viewer's window on the default scene, 480×320 under Xvfb
# Needs ImageMagick (montage, convert) and the DejaVu fonts to compose them, Xvfb for the viewer.
# Usage: scripts/readme-scenes.sh [TAG] [extra diffract options]   (default tag: lavapipe)
source "$(dirname "$0")/lib/readme.sh"
img=docs/images
log=docs/profile/scenes-$tag.txt
font=DejaVu-Sans
: >"$log"

run render --out $img/snake.png --width 800 --height 800 "$@"
run map --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \
  --coherence-um 20 --approach baked --footprint --size 201 --light-theta 0 --exposure 8 --out "$scratch/map.png" "$@"
gpu=$(grep -o 'GPU [0-9.]* ms for its one frame' "$log" | head -1 | grep -o '[0-9.]*' | head -1)
convert "$scratch/map.png" -bordercolor '#909090' -border 2 "$scratch/inset.png"
convert $img/snake.png \
  "$scratch/inset.png" -gravity SouthWest -geometry +16+40 -composite \
  -font $font -fill '#e0e0e0' -pointsize 17 -gravity SouthWest \
  -annotate +18+14 "the material's BRDF map: light at normal incidence" \
  -gravity NorthWest -pointsize 22 \
  -annotate +16+14 "baked approach (the default): the spectrum integrated ahead of time" \
  -pointsize 18 \
  -annotate +16+46 "measured Elaphe guttata AFM scan, tiled 10×, 20 µm coherence, under a clear sky" \
  -annotate +16+72 "4× multisampling · $gpu ms of GPU time on lavapipe (llvmpipe, 2 cores)" \
  $img/snake-annotated.png

for scene in elaphe-snake-sun xenopeltis-snake blazed-disk elaphe-sphere; do
  DIFFRACT_CACHE="$scratch/cache" run render assets/scenes/$scene.toml --out "$scratch/$scene.png" \
    --width 320 --height 320 "$@"
done
montage -font $font -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'elaphe-snake-sun (measured)' "$scratch/elaphe-snake-sun.png" \
  -label 'xenopeltis-snake (measured)' "$scratch/xenopeltis-snake.png" \
  -label 'blazed-disk' "$scratch/blazed-disk.png" \
  -label 'elaphe-sphere (measured)' "$scratch/elaphe-sphere.png" \
  -tile 4x1 -geometry +3+3 $img/scenes.png

run render --frames 6 --light-sweep --turn-deg 50 --width 240 --height 240 --out "$scratch/sweep.png" "$@"
montage -background '#202020' "$scratch"/sweep_000{1..6}.png -tile 6x1 -geometry +2+2 $img/light-sweep.png

if command -v Xvfb >/dev/null; then
  start_xvfb 94 640x480
  run view --width 480 --height 320 --frames 30 --screenshot $img/view.png "$@" | grep -v '^  '
fi
