#!/usr/bin/env bash
# A soak of the viewer under Xvfb (release build, validation layer on): the default scene for N frames (1000
# unless given), the window resized and the approach switched every 50 frames (flss → nmm → pq → gem → baked →
# …). Fails on any validation message, on a GPU allocation live at teardown, or on any error; prints resident
# memory after the first frame, after the first round of approaches and at the end. Output in docs/soak-view.txt.
# Usage: scripts/soak-view.sh [FRAMES] [WIDTH HEIGHT]     (default 1000 frames at 64×48. FLSS, NMM and PQ frames
# of the default scene cost about a second or more each on lavapipe even at that size: the soak takes tens of
# minutes on 2 cores. CARGO_TARGET_DIR picks the build folder.)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/xvfb.sh
frames=${1:-1000}
width=${2:-64}
height=${3:-48}
cargo build --release -q
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"; [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true' EXIT
start_xvfb 96 800x600
out=docs/soak-view.txt
{
  echo "# scripts/soak-view.sh $frames $width $height ($(date -u +%Y-%m-%d), $(nproc) cores)"
  echo "\$ diffract view --width $width --height $height --frames $frames --soak --vsync off --validation"
} > "$tmp/log"
start=$(date +%s)
set +e
DISPLAY=:96 DIFFRACT_CACHE="$tmp/cache" "${CARGO_TARGET_DIR:-target}/release/diffract" view --width "$width" --height "$height" \
  --frames "$frames" --soak --vsync off --validation >> "$tmp/log" 2>&1
rc=$?
set -e
echo "exit status $rc after $(( $(date +%s) - start )) s" >> "$tmp/log"
grep -v -e '^mouse:' -e '^keys:' -e '^       ' "$tmp/log" > "$out" || true
cat "$out"
exit "$rc"
