#!/usr/bin/env bash
# The full extremes grid (tests/extremes.rs, `full_grid`): the measured scans at 1×–16× their heights, patches
# from 2² to 4096², coherence 1 µm–1 m, lights and views up to 89.99°, 360–830 nm, through every evaluator of P
# (exact, taylor, taylor-f32, the GPU's compute shader on lavapipe) and a BRDF map per approach. Every
# evaluation must pass (finite, within the tolerance of exact) or be refused with its reason; any failure
# fails the script. Its summary is written to docs/extremes.md (docs/reliability.md quotes it).
# Usage: scripts/extremes.sh        (release build; about half an hour on a 2-core machine)
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/extremes.md
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
DIFFRACT_EXTREMES_OUT="$tmp" cargo test --release --test extremes -- --ignored --nocapture full_grid
{
  echo "# The extremes grid"
  echo
  echo "Made by \`scripts/extremes.sh\` ($(date -u +%Y-%m-%d), $(nproc) cores, lavapipe). Each row is one evaluator;"
  echo "an evaluation is one call (a patch, coherence length, light and wavelength with every view, or one map)."
  echo "*worst* is the largest amplitude difference | |P| − |P_exact| | among the passes (tolerance 1e-4 on"
  echo "|P − P_N|, pass ≤ 2e-4), or for maps the largest mean CIEDE2000 against the exact reference image."
  echo
  cat "$tmp"
} > "$out"
echo "wrote $out"
