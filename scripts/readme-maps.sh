#!/usr/bin/env bash
# The surface maps' picture and speed (docs/usage.md, "Pigment and normal maps"); the commands' output lands in
# docs/profile/maps.txt:
#   docs/images/skin-maps.png  assets/scenes/skin-maps.toml at 384×256 (both maps), beside the same scene with the
#                              pigment map alone and with no map, at the scene's exposure
#   the cost of maps against no maps at 800² (1 and 4 samples), twice each, alternating: skin-maps.toml against its
#   copy without maps and against a copy whose normal map is flat (its maps' reads without the wider table its
#   scales' normals need), and the default scene against a copy whose soil reads a pigment map (5 cm a repeat)
# Needs ImageMagick (montage) and the DejaVu fonts to compose the picture.
# Usage: scripts/readme-maps.sh [TAG] [extra diffract options]
source "$(dirname "$0")/lib/readme.sh"
log=docs/profile/maps.txt
: >"$log"
sed -e "s|\"\.\./|\"$PWD/assets/|" assets/scenes/skin-maps.toml >"$scratch/maps.toml"
grep -v '^normal_map' "$scratch/maps.toml" >"$scratch/pigment-only.toml"
grep -v '^normal_map\|^pigment_map\|^map_size_m' "$scratch/maps.toml" >"$scratch/no-maps.toml"
convert -size 8x8 'xc:rgb(128,128,255)' "PNG24:$scratch/flat-normal.png"
sed -e "s|^normal_map = .*|normal_map = \"$scratch/flat-normal.png\"|" "$scratch/maps.toml" >"$scratch/flat-normal-map.toml"
sed -e "s|\"\.\./|\"$PWD/assets/|" assets/scenes/elaphe-snake.toml >"$scratch/default.toml"
awk -v map="$PWD/assets/maps/scales-pigment.png" '{print} /^\[material\.soil\]/{print "pigment_map = \"" map "\"\nmap_size_m = 0.05"}' \
  "$scratch/default.toml" >"$scratch/default-soil-map.toml"
grep -q '^pigment_map' "$scratch/default-soil-map.toml"
for s in maps pigment-only no-maps; do
  run render "$scratch/$s.toml" --out "$scratch/$s.png" "$@"
done
montage -font DejaVu-Sans -pointsize 15 -fill '#e0e0e0' -background '#202020' \
  -label 'pigment and normal maps' "$scratch/maps.png" \
  -label 'pigment map alone' "$scratch/pigment-only.png" \
  -label 'no maps' "$scratch/no-maps.png" \
  -tile 3x1 -geometry +3+3 docs/images/skin-maps.png
for round in 1 2; do
  for s in no-maps flat-normal-map maps default default-soil-map; do
    run profile "$scratch/$s.toml" --width 800 --height 800 --frames 10 --warmup 3 --no-reference \
      --sweep samples=1,4 "$@"
  done
done
