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
device_args=()
source scripts/lib/user-paths.sh
check_offscreen_paths

if command -v Xvfb >/dev/null; then
  start_xvfb 97 800x600
  check_viewer_paths
else
  echo "FAIL  viewer: Xvfb is not installed (scripts/setup-debian.sh installs it)"
  failures=$((failures + 1))
fi

if [ "$failures" -gt 0 ]; then
  echo "check-release: $failures user path(s) failed in the release build"
  exit 1
fi
echo "check-release: every user path is validation-clean in the release build"
