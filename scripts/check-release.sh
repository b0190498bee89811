#!/usr/bin/env bash
# The paths users run, in a release build with the Khronos validation layer: any validation message, error or
# non-zero exit fails the script. The SPIR-V optimiser of a release build can strip what a debug build keeps
# (an unused vertex input, then a validation warning), so `cargo test` alone does not cover these.
# Usage: scripts/check-release.sh   (CI runs it; it needs what scripts/setup-debian.sh installs)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/xvfb.sh

cargo build --release --quiet
bin=target/release/diffract
out=$(mktemp -d)
trap 'rm -rf "$out"; [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true' EXIT
export DIFFRACT_CACHE="$out/cache"
failures=0

check() {
  local name=$1; shift
  local start=$SECONDS
  if "$@" --validation >"$out/$name.log" 2>&1; then
    echo "ok    $name ($((SECONDS - start)) s)"
  else
    echo "FAIL  $name: $*"
    sed 's/^/      /' "$out/$name.log" | tail -20
    failures=$((failures + 1))
  fi
}

check default-scene "$bin" render --out "$out/default.png" --width 64 --height 64
for scene in assets/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  check "scene-$name" "$bin" render "$scene" --out "$out/$name.png" --width 64 --height 64
done
check preview "$bin" render --out "$out/preview.png" --width 64 --height 64 --preview
check sequence "$bin" render assets/scenes/blazed-disk.toml --out "$out/turn.png" --width 48 --height 48 \
  --frames 3 --orbit
check flss-scene "$bin" render --out "$out/flss.png" --width 32 --height 32 --approach flss
check map "$bin" map --heightfield assets/patches/blazed-1.6um.gsf --light-theta 20 --size 64 \
  --out "$out/map.png" --exr "$out/map.exr"
check map-baked "$bin" map --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 --height-um 0.375 \
  --tile 10 --light-theta 20 --size 64 --approach baked --out "$out/map-baked.png"
check brdf-gpu "$bin" brdf --heightfield assets/patches/blazed-1.6um.gsf --light-theta 0 --view-theta 0:40:10 \
  --lambda 450,550 --gpu
check profile "$bin" profile --width 32 --frames 2 --warmup 1 --no-reference --sweep approach=flss,baked
check devices "$bin" devices

if command -v Xvfb >/dev/null; then
  start_xvfb 97 800x600
  check viewer "$bin" view --width 160 --height 120 --frames 20 --screenshot "$out/view.png"
  check viewer-flss "$bin" view --width 96 --height 64 --frames 3 --approach flss
else
  echo "FAIL  viewer: Xvfb is not installed (scripts/setup-debian.sh installs it)"
  failures=$((failures + 1))
fi

if [ "$failures" -gt 0 ]; then
  echo "check-release: $failures user path(s) failed in the release build"
  exit 1
fi
echo "check-release: every user path is validation-clean in the release build"
