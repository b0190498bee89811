#!/usr/bin/env bash
# The picture of the built-in clear sky (docs/usage.md): `diffract gen sky` previews at 512×256 for a sun 10°,
# 35° and 70° high under a clear sky (turbidity 2.5) and the 35° sun through haze (turbidity 8), all at one
# exposure (-14 EV) so that their brightness compares; the commands' output lands in docs/profile/sky.txt:
#   docs/images/sky.png
# Needs ImageMagick (montage) and the DejaVu fonts to compose it. (The sky is computed on the CPU: no device.)
# Usage: scripts/readme-sky.sh
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/sky.txt
: >"$log"
for case in "10 2.5" "35 2.5" "70 2.5" "35 8"; do
  set -- $case
  run gen sky --sun-elevation-deg "$1" --turbidity "$2" --width 512 --exposure -14 --out "$scratch/sky-$1-$2.png"
done
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'sun 10° high, turbidity 2.5' "$scratch/sky-10-2.5.png" \
  -label 'sun 35° high, turbidity 2.5' "$scratch/sky-35-2.5.png" \
  -label 'sun 70° high, turbidity 2.5' "$scratch/sky-70-2.5.png" \
  -label 'sun 35° high, turbidity 8 (haze)' "$scratch/sky-35-8.png" \
  -tile 2x2 -geometry +3+3 docs/images/sky.png
