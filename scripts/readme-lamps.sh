#!/usr/bin/env bash
# The lamps' picture and speed (docs/usage.md, "Lamps"); the commands' output lands in docs/profile/lamps.txt:
#   docs/images/bench.png  assets/scenes/bench.toml at 320×240 (a skin sample under a lamp 2 cm across at 20 cm: the
#                          lamp's size sets the coherence), beside the same scene with the material's coherence set to
#                          65.0001 µm (the window of a point-like light) at the same exposure
#   docs/images/flash.png  assets/scenes/elaphe-snake-flash.toml at 320×240 (the snake under a flash beside the
#                          camera: the lamp's shadow), beside the same with [light] shadows = false
#   the cost of a point lamp against the sun in the same scene: bench.toml, and a copy lit by the sun from the lamp's
#   direction instead, profiled at 800² (1 and 4 samples), twice each, alternating
# Needs ImageMagick (montage) and the DejaVu fonts to compose the picture.
# Usage: scripts/readme-lamps.sh [TAG] [extra diffract options]
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/lamps.txt
: >"$log"
sed -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" assets/scenes/bench.toml >"$scratch/bench.toml"
sed -e 's|^tile = 10$|tile = 10\ncoherence_um = 65.0001|' "$scratch/bench.toml" >"$scratch/point-like.toml"
# The sun from the lamp's direction, no lamp: the [[lamp]] table left out.
awk '/^\[\[lamp\]\]/{skip=1} /^\[\[object\]\]/{skip=0} !skip' "$scratch/bench.toml" |
  sed -e 's|^environment = "none".*|direction = [0.0, 0.1414, -0.1414]\nenvironment = "none"|' >"$scratch/sun.toml"
run render "$scratch/bench.toml" --width 320 --height 240 --out "$scratch/bench.png" "$@"
run render "$scratch/point-like.toml" --width 320 --height 240 --out "$scratch/point-like.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'coherence from the lamp: 6 µm' "$scratch/bench.png" \
  -label 'coherence_um = 65.0001' "$scratch/point-like.png" \
  -tile 2x1 -geometry +3+3 docs/images/bench.png
sed -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" assets/scenes/elaphe-snake-flash.toml >"$scratch/flash.toml"
sed -e 's|^environment = "none".*|environment = "none"\nshadows = false|' "$scratch/flash.toml" >"$scratch/unshadowed.toml"
run render "$scratch/flash.toml" --width 320 --height 240 --out "$scratch/flash.png" "$@"
run render "$scratch/unshadowed.toml" --width 320 --height 240 --out "$scratch/unshadowed.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'a flash beside the camera: its shadow' "$scratch/flash.png" \
  -label 'shadows = false' "$scratch/unshadowed.png" \
  -tile 2x1 -geometry +3+3 docs/images/flash.png
for round in 1 2; do
  for scene in sun bench; do
    run profile "$scratch/$scene.toml" --width 800 --height 800 --frames 10 --warmup 3 --no-reference \
      --sweep samples=1,4 "$@"
  done
done
