#!/usr/bin/env bash
# The pictures of the built-in clear sky (docs/usage.md); the commands' output lands in docs/profile/sky.txt:
#   docs/images/sky.png        `diffract gen sky` previews at 512×256 for a sun 10°, 35° and 70° high under a clear
#                              sky (turbidity 2.5) and the 35° sun through haze (turbidity 8), Hosek–Wilkie's; and
#                              Preetham's sky for the 10° and 35° suns (--sky-model preetham), all at one exposure
#                              (-14 EV) so that their brightness compares
#   docs/images/environment-map.png  a ball under a map written by gen sky --no-sun, and under the sky
#   docs/images/snake-ground.png  elaphe-snake-ground.toml at 320×240, with its shadow and with shadows = false
#   docs/images/snake-sky.png  elaphe-snake-sun.toml (the sun alone, relative units) beside the default scene (the
#                              clear sky, physical units) at 256², on the device (lavapipe unless options say otherwise)
#   docs/images/hdri-snake.png the default scene beside elaphe-snake-hdri.toml (a camera-made HDRI with its own sun,
#                              relative units) at 256²
# Needs ImageMagick (montage) and the DejaVu fonts to compose them.
# Usage: scripts/readme-sky.sh [TAG] [extra diffract options]
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/sky.txt
: >"$log"
for case in "10 2.5 hosek-wilkie" "35 2.5 hosek-wilkie" "70 2.5 hosek-wilkie" "35 8 hosek-wilkie" \
  "10 2.5 preetham" "35 2.5 preetham"; do
  read -r elevation turbidity model <<<"$case"
  run gen sky --sun-elevation-deg "$elevation" --turbidity "$turbidity" --sky-model "$model" --width 512 \
    --exposure -14 --out "$scratch/sky-$elevation-$turbidity-$model.png"
done
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'sun 10° high, turbidity 2.5' "$scratch/sky-10-2.5-hosek-wilkie.png" \
  -label 'sun 35° high, turbidity 2.5' "$scratch/sky-35-2.5-hosek-wilkie.png" \
  -label 'sun 70° high, turbidity 2.5' "$scratch/sky-70-2.5-hosek-wilkie.png" \
  -label 'sun 35° high, turbidity 8 (haze)' "$scratch/sky-35-8-hosek-wilkie.png" \
  -label 'Preetham 1999: sun 10°, turbidity 2.5' "$scratch/sky-10-2.5-preetham.png" \
  -label 'Preetham 1999: sun 35°, turbidity 2.5' "$scratch/sky-35-2.5-preetham.png" \
  -tile 2x3 -geometry +3+3 docs/images/sky.png
run render assets/scenes/elaphe-snake-sun.toml --width 256 --height 256 --out "$scratch/sun.png" "$@"
run render --width 256 --height 256 --out "$scratch/sky.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'the sun alone (relative units)' "$scratch/sun.png" \
  -label 'the default: under the sky' "$scratch/sky.png" \
  -tile 2x1 -geometry +3+3 docs/images/snake-sky.png
# The snake on the ground with the sun's shadow, beside the same scene with `shadows = false` (a copy whose
# paths point back into assets/).
run render assets/scenes/elaphe-snake-ground.toml --width 320 --height 240 --out "$scratch/ground.png" "$@"
sed -e 's|^turbidity = 3.0|turbidity = 3.0\nshadows = false|' -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" \
  assets/scenes/elaphe-snake-ground.toml >"$scratch/no-shadows.toml"
run render "$scratch/no-shadows.toml" --width 320 --height 240 --out "$scratch/no-shadows.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'on the ground, with the sun'"'"'s shadow' "$scratch/ground.png" \
  -label 'shadows = false' "$scratch/no-shadows.png" \
  -tile 2x1 -geometry +3+3 docs/images/snake-ground.png
# A user's HDR map: the clear sky around a 35° sun without its sun, written by gen sky, lighting and drawn behind a
# ball on a small ground; beside it the same scene under environment = "sky".
run gen sky --sun-elevation-deg 35 --no-sun --width 512 --out "$scratch/around.exr"
cat >"$scratch/map.toml" <<'SCENE'
[camera]
position = [0.0, 0.6, -3.0]
target = [0.0, 0.8, 0.0]
fov_y_deg = 70.0

[light]
direction = [0.0, 0.5736, 0.8192]   # the map's sun: 35° up, azimuth 0 (+z)
environment = "around.exr"

[[object]]
shape = "sphere"
material = "grey"
scale = 0.5
translate = [0.0, 0.5, 0.0]

[[object]]
shape = "ground"
material = "grey"
scale = 0.05

[material.grey]
pigment = [0.5, 0.5, 0.5]

[render]
exposure_ev = 15.1
SCENE
sed 's/^environment = "around.exr"/environment = "sky"/' "$scratch/map.toml" >"$scratch/sky.toml"
run render "$scratch/map.toml" --width 320 --height 200 --out "$scratch/map.png" "$@"
run render "$scratch/sky.toml" --width 320 --height 200 --out "$scratch/sky-ball.png" "$@"
# The snake on the ground under a user's map: a hazy sky (turbidity 8) around the scene's sun, 26.8° high at
# azimuth -137.7° (its [light] direction), written without its sun.
run gen sky --sun-elevation-deg 26.77 --sun-azimuth-deg -137.73 --turbidity 8 --no-sun --width 512 \
  --out "$scratch/hazy.exr"
sed -e 's|^environment = "sky".*|environment = "hazy.exr"|' -e '/^turbidity = /d' \
  -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" assets/scenes/elaphe-snake-ground.toml >"$scratch/hazy.toml"
run render "$scratch/hazy.toml" --width 320 --height 200 --out "$scratch/hazy.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'a map: gen sky --no-sun' "$scratch/map.png" \
  -label 'environment = "sky"' "$scratch/sky-ball.png" \
  -label 'the snake under a hazy map' "$scratch/hazy.png" \
  -tile 3x1 -geometry +3+3 docs/images/environment-map.png
# A camera-made HDRI with its own sun (relative units), beside the default scene under the built-in sky.
run render assets/scenes/elaphe-snake-hdri.toml --width 256 --height 256 --out "$scratch/hdri.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'the default: the built-in sky' "$scratch/sky.png" \
  -label 'a photographed sky with its sun' "$scratch/hdri.png" \
  -tile 2x1 -geometry +3+3 docs/images/hdri-snake.png
