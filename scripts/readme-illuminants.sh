#!/usr/bin/env bash
# The picture of illuminants (docs/usage.md): the snake under the sun alone (elaphe-snake-sun.toml) at 256² under CIE D65, A (tungsten) and F11 (a
# three-band fluorescent lamp), each from the diffract command its log line names (lavapipe on this project's
# machine unless extra options, e.g. --device 0, say otherwise); the commands' output lands in
# docs/profile/illuminants-<tag>.txt:
#   docs/images/illuminants.png
# Needs ImageMagick (montage) and the DejaVu fonts to compose it.
# Usage: scripts/readme-illuminants.sh [TAG] [extra diffract options]   (default tag: lavapipe)
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/illuminants-$tag.txt
: >"$log"
for light in D65 A F11; do
  run render assets/scenes/elaphe-snake-sun.toml --illuminant $light --width 256 --height 256 --out "$scratch/$light.png" "$@"
done
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'D65 (daylight, the default)' "$scratch/D65.png" \
  -label 'A (tungsten, 2856 K)' "$scratch/A.png" \
  -label 'F11 (three-band fluorescent)' "$scratch/F11.png" \
  -tile 3x1 -geometry +3+3 docs/images/illuminants.png
