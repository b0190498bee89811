# Sourced by scripts/check-release.sh and scripts/gpu-check.sh: the paths users run, each with the Khronos
# validation layer; any validation message, error or non-zero exit counts as a failure.
# Needs: $bin (the diffract binary), $out (a scratch folder), and optionally the array $device_args (e.g.
# (--device 0)), added to every command. Leaves the count of failed paths in $failures.
failures=0

check() {
  local name=$1; shift
  local start=$SECONDS
  if "$@" "${device_args[@]}" --validation >"$out/$name.log" 2>&1; then
    echo "ok    $name ($((SECONDS - start)) s)"
  else
    echo "FAIL  $name: $* ${device_args[*]}"
    sed 's/^/      /' "$out/$name.log" | tail -20
    failures=$((failures + 1))
  fi
}

# Every command but the viewer's.
check_offscreen_paths() {
  check default-scene "$bin" render --out "$out/default.png" --width 64 --height 64
  for scene in assets/scenes/*.toml; do
    local name
    name=$(basename "$scene" .toml)
    check "scene-$name" "$bin" render "$scene" --out "$out/$name.png" --width 64 --height 64
  done
  # A user's HDR environment map: the sky around its sun written by gen sky, behind and around the ground scene.
  check sky-map "$bin" gen sky --no-sun --width 64 --out "$out/around.exr"
  sed -e 's|^environment = "sky".*|environment = "around.exr"|' -e '/^turbidity = /d' \
    -e "s|\"\.\./afm/|\"$PWD/assets/afm/|" assets/scenes/elaphe-snake-ground.toml >"$out/map-scene.toml"
  check scene-env-map "$bin" render "$out/map-scene.toml" --out "$out/map-scene.png" --width 64 --height 64
  # The same map without a [light] direction: no sun in it, so the map lights the scene alone (no directional light).
  sed -e '/^direction = /d' "$out/map-scene.toml" >"$out/map-alone.toml"
  check scene-map-alone "$bin" render "$out/map-alone.toml" --out "$out/map-alone.png" --width 64 --height 64
  check preview "$bin" render --out "$out/preview.png" --width 64 --height 64 --preview
  check sequence "$bin" render assets/scenes/blazed-disk.toml --out "$out/turn.png" --width 48 --height 48 \
    --frames 3 --orbit
  check flss-scene "$bin" render --out "$out/flss.png" --width 32 --height 32 --approach flss
  check map "$bin" map --heightfield assets/patches/blazed-1.6um.gsf --light-theta 20 --size 64 \
    --out "$out/map.png" --exr "$out/map.exr"
  check map-baked "$bin" map --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 \
    --tile 10 --light-theta 20 --size 64 --approach baked --out "$out/map-baked.png"
  check map-lamp "$bin" map --heightfield assets/patches/blazed-1.6um.gsf --light-theta 45 --lamp-radius-m 0.01 \
    --lamp-distance-m 0.2 --size 64 --approach baked --out "$out/map-lamp.png"
  check brdf-gpu "$bin" brdf --heightfield assets/patches/blazed-1.6um.gsf --light-theta 0 --view-theta 0:40:10 \
    --lambda 450,550 --gpu
  check profile "$bin" profile --width 32 --frames 2 --warmup 1 --no-reference --sweep approach=flss,baked
  # Maps through the profiler: the counting variant and the G-buffer that feeds the exact reference.
  check profile-maps "$bin" profile assets/scenes/skin-maps.toml --width 32 --height 24 --frames 2 --warmup 1 \
    --reference-pixels 20 --reference-samples 1
  check devices "$bin" devices
}

# The viewer's paths (a display must be set).
check_viewer_paths() {
  check viewer "$bin" view --width 160 --height 120 --frames 20 --screenshot "$out/view.png"
  check viewer-flss "$bin" view --width 96 --height 64 --frames 3 --approach flss
  check viewer-lamp "$bin" view assets/scenes/bench.toml --width 96 --height 64 --frames 5 --screenshot "$out/bench.png"
  check viewer-maps "$bin" view assets/scenes/skin-maps.toml --width 96 --height 64 --frames 3 \
    --screenshot "$out/skin-maps.png"
  check viewer-lamp-shadow "$bin" view assets/scenes/elaphe-snake-flash.toml --width 96 --height 64 --frames 3 \
    --screenshot "$out/flash.png"
}
