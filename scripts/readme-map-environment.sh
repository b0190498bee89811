#!/usr/bin/env bash
# The BRDF map under an environment (docs/usage.md, docs/model.md §3.10); the commands' output lands in
# docs/profile/map-environment.txt:
#   docs/images/map-environment.png  the blazed grating's map under one directional light (the sun of the sky at
#                                    the same place, baked) beside its map under the clear sky with its sun
#                                    (`map --environment`, 1024 samples per pixel), each at its own measured exposure,
#                                    with the map checked against the exact reference at 32 random pixels
# Needs ImageMagick (montage) and the DejaVu fonts to compose them.
# Usage: scripts/readme-map-environment.sh [TAG] [extra diffract options]
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/map-environment.txt
: >"$log"
run gen patch blazed --out "$scratch/blaze.gsf"
# The sun 50° high at azimuth 0: in the map's frame (zenith = normal, azimuth 0 = the patch's −y) the light is
# θ_i = 40°, φ_i = 270°.
run gen sky --sun-elevation-deg 50 --out "$scratch/sky.exr"
run map --heightfield "$scratch/blaze.gsf" --light-theta 40 --light-phi 270 --approach baked --size 256 \
  --out "$scratch/sun.png" "$@"
run map --heightfield "$scratch/blaze.gsf" --environment "$scratch/sky.exr" --size 256 --env-samples 1024 \
  --env-reference 32 --out "$scratch/sky.png" "$@"
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'one light (the sun alone)' "$scratch/sun.png" \
  -label 'under the clear sky and its sun' "$scratch/sky.png" \
  -tile 2x1 -geometry +3+3 docs/images/map-environment.png
# Samples against accuracy: the same map at 128² for 64 to 4096 samples per pixel, each against the exact reference
# at the same 32 pixels (GPU ms and mean ΔE00 in the log).
for n in 64 256 1024 4096; do
  run map --heightfield "$scratch/blaze.gsf" --environment "$scratch/sky.exr" --size 128 --env-samples "$n" \
    --env-reference 32 --out "$scratch/sky-$n.png" "$@"
done
