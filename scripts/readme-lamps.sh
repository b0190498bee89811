#!/usr/bin/env bash
# The lamps' picture and speed (docs/usage.md, "Lamps"); the commands' output lands in docs/profile/lamps.txt:
#   docs/images/bench.png  assets/scenes/bench.toml at 320×240 (a skin sample under a lamp 2 cm across at 20 cm: the
#                          lamp's size sets the coherence), beside the same scene with the material's coherence set to
#                          65.0001 µm (the window of a point-like light) at the same exposure
#   docs/images/flash.png  assets/scenes/elaphe-snake-flash.toml at 320×240 (the snake under a flash beside the
#                          camera: the lamp's shadow), beside the same with [light] shadows = false
#   the cost of a point lamp against the sun in the same scene: bench.toml and elaphe-snake-flash.toml (its shadow
#   too), each beside a copy lit by the sun from the lamp's direction instead, and the flash scene without shadows,
#   profiled at 800² (1 and 4 samples), twice each, alternating
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
# Two scenes rendered at 320×240 side by side, labelled: pair OUT.png LABEL1 SCENE1 LABEL2 SCENE2 [options].
pair() {
  local out=$1 l1=$2 s1=$3 l2=$4 s2=$5
  shift 5
  run render "$scratch/$s1.toml" --width 320 --height 240 --out "$scratch/$s1.png" "$@"
  run render "$scratch/$s2.toml" --width 320 --height 240 --out "$scratch/$s2.png" "$@"
  montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
    -label "$l1" "$scratch/$s1.png" -label "$l2" "$scratch/$s2.png" -tile 2x1 -geometry +3+3 "$out"
}
pair docs/images/bench.png 'coherence from the lamp: 6 µm' bench 'coherence_um = 65.0001' point-like "$@"
sed -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" assets/scenes/elaphe-snake-flash.toml >"$scratch/flash.toml"
sed -e 's|^environment = "none".*|environment = "none"\nshadows = false|' "$scratch/flash.toml" >"$scratch/unshadowed.toml"
pair docs/images/flash.png 'a flash beside the camera: its shadow' flash 'shadows = false' unshadowed "$@"
# The sun from the flash's direction (from the snake's middle, the camera's target), no lamp: it casts its shadow.
awk '/^\[\[lamp\]\]/{skip=1} /^\[\[object\]\]/{skip=0} !skip' "$scratch/flash.toml" |
  sed -e 's|^environment = "none".*|direction = [1.10, 0.75, 0.347]\nenvironment = "none"|' >"$scratch/flash-sun.toml"
for round in 1 2; do
  for scene in sun bench flash-sun flash unshadowed; do
    run profile "$scratch/$scene.toml" --width 800 --height 800 --frames 10 --warmup 3 --no-reference \
      --sweep samples=1,4 "$@"
  done
done
