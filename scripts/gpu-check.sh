#!/usr/bin/env bash
# On whatever Vulkan device is present: every user path with the validation layer, the GPU tests (prebuilt test
# binaries, so a machine without Rust runs them), and a timing table with per-pass times. Any validation
# message, failed path or failed test fails the script; the timings are printed and kept, never judged.
#
# Usage: scripts/gpu-check.sh [--device N|NAME] [--out DIR] [--quick] [--bin-dir DIR]
#        scripts/gpu-check.sh --bundle DIR
#   --device   the device (an index or a name substring from `diffract devices`; default: the first discrete
#              GPU, then integrated GPU, then whatever is listed first)
#   --out      where the logs, CSV files and tables go (default: a fresh temporary folder, printed at the end)
#   --quick    smaller timing workloads (800² frames and maps up to 1024²), for a CPU device such as lavapipe
#   --bin-dir  where diffract and deps/<test binaries> are (default: target/release)
#   --bundle   copy diffract and the newest test binaries it runs into DIR/target/release (about 31 MB), to carry
#              to another machine with the working tree, and stop
#
# On this machine: `cargo build --release && cargo test --release --no-run` makes target/release/diffract and
# the test binaries under target/release/deps; the script itself needs neither cargo nor Rust. To run it on a
# machine lent for a session, make a bundle inside the working tree (an ignored folder), carry it, and run the
# script there with --bin-dir (the test binaries find the repository's assets and the diffract binary above
# themselves). docs/performance.md gives the recipe.
set -euo pipefail
cd "$(dirname "$0")/.."

device=""
out=""
quick=0
bin_dir=target/release
bundle=""
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --bin-dir) bin_dir=$2; shift 2 ;;
    --bundle) bundle=$2; shift 2 ;;
    -h|--help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu-check: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

test_names=(gpu cli cli_render cli_brdf cli_profile cli_view)
# The newest test binary named $1 under $bin_dir/deps (cargo adds a hash to the name).
test_binary() {
  find "$bin_dir/deps" -maxdepth 1 -type f -executable -name "$1-*" -printf '%T@ %p\n' 2>/dev/null \
    | sort -rn | head -1 | cut -d' ' -f2-
}

bin=$bin_dir/diffract
if [ -n "$bundle" ]; then
  if command -v cargo >/dev/null; then
    cargo build --release -q || exit 2
    cargo test --release --no-run -q || exit 2
  fi
  rm -rf "$bundle/target/release"
  mkdir -p "$bundle/target/release/deps"
  cp "$bin" "$bundle/target/release/"
  for name in "${test_names[@]}"; do
    test_bin=$(test_binary "$name")
    [ -n "$test_bin" ] || { echo "gpu-check: no $name test binary (cargo test --release --no-run)" >&2; exit 2; }
    cp "$test_bin" "$bundle/target/release/deps/"
  done
  echo "gpu-check: bundle in $bundle/target/release ($(du -sh "$bundle" | cut -f1)); run it with --bin-dir $bundle/target/release"
  exit 0
fi
if [ ! -x "$bin" ]; then
  echo "gpu-check: $bin is missing: run \`cargo build --release\` first" >&2
  exit 2
fi
out=${out:-$(mktemp -d)}
mkdir -p "$out"
export DIFFRACT_CACHE="$out/cache"

# The device: as asked, else the one a user gets by default (a discrete GPU first).
"$bin" devices | tee "$out/devices.txt"
if [ -z "$device" ]; then
  for kind in "discrete GPU" "integrated GPU" ""; do
    device=$(awk -v k="$kind" 'NR > 1 && index($0, k) { print $1; exit }' "$out/devices.txt")
    [ -n "$device" ] && break
  done
fi
echo "gpu-check: device $device"
device_args=(--device "$device")

echo "== user paths, with the validation layer"
source scripts/lib/user-paths.sh
check_offscreen_paths
if [ -n "${DISPLAY:-}" ]; then
  check_viewer_paths
else
  echo "skip  viewer: no display (DISPLAY is not set)"
fi

echo "== GPU tests on device $device"
export DIFFRACT_TEST_DEVICE=$device DIFFRACT_TEST_TMP="$out/tests"
mkdir -p "$DIFFRACT_TEST_TMP"
tests=0
for name in "${test_names[@]}"; do
  if [ "$name" = cli_view ] && [ -z "${DISPLAY:-}" ]; then
    echo "skip  tests cli_view: no display"
    continue
  fi
  test_bin=$(test_binary "$name")
  if [ -z "$test_bin" ]; then
    echo "FAIL  tests $name: no test binary (cargo test --release --no-run)"
    failures=$((failures + 1))
    continue
  fi
  if "$test_bin" --test-threads 2 >"$out/test-$name.log" 2>&1; then
    echo "ok    tests $name: $(grep -h '^test result' "$out/test-$name.log" | tail -1)"
  else
    echo "FAIL  tests $name ($test_bin; log $out/test-$name.log):"
    # The panics, or (a binary killed by a signal prints none) the log's last lines.
    { grep -E "panicked|FAILED|failures:" "$out/test-$name.log" || tail -5 "$out/test-$name.log"; } \
      | head -20 | sed 's/^/      /'
    failures=$((failures + 1))
  fi
  tests=$((tests + 1))
done

echo "== timings on device $device (GPU ms; the passes of a frame sum to its time)"
# A map's first frames after its table's upload run slower on an H100 (2048², baked: 19.9 ms median over frames
# 3–12, 5.8 ms over frames 11–70), so a GPU's maps are timed after 20 warm-up frames.
# A scene's configuration can start the same way (the GPU idles while the CPU prepares it): on an H100 at de6cb65
# the default scene's 1920×1080 frame read 7.38 ms after 5 warm-up frames in one run and 1.91 in three others
# (the upload's GPU time doubled with it, as at a lower clock), so scenes get 20 warm-up frames too (not yet
# checked on a GPU: compare a row's upload time with the other rows').
if [ "$quick" = 1 ]; then
  frames=(800x800) scene_frames=10 scene_warmup=2 map_sizes=256,512,1024 map_frames=10 map_warmup=2
else
  frames=(1920x1080 3840x2160) scene_frames=20 scene_warmup=20 map_sizes=256,512,1024,2048,4096 map_frames=30 \
    map_warmup=20
fi
# The default scene (the snake under the clear sky; its diffraction at the vertices and per pixel) and the same
# snake under the sun alone (what the sky costs), each also as the viewer draws it (8-bit sRGB frames, timed
# without a window: target=display) and through a visibility buffer (path=visibility, linear frames).
for size in "${frames[@]}"; do
  w=${size%x*} h=${size#*x}
  for scene in default sun; do
    name=scene-$size args=()
    sweep=(samples=1,4 sky_at=vertex,pixel --sweep samples=1,4 target=display --sweep samples=1,4 path=visibility)
    [ "$scene" = sun ] && name=scene-sun-$size args=(assets/scenes/elaphe-snake-sun.toml) \
      sweep=(samples=1,4 target=linear,display --sweep samples=1,4 path=visibility)
    "$bin" profile "${args[@]}" "${device_args[@]}" --width "$w" --height "$h" --frames "$scene_frames" \
      --warmup "$scene_warmup" --no-reference --sweep "${sweep[@]}" --csv "$out/$name.csv" >"$out/$name.md" 2>"$out/$name.err" \
      || { echo "FAIL  timing $name"; cat "$out/$name.err"; failures=$((failures + 1)); }
    echo "-- $scene scene at $size"
    sed -n '/^| configuration/,$p' "$out/$name.md"
  done
done
# The viewer's and sequences' table (any light and view) at the first size, as the window draws it: in one or two
# segments of w (6 RGBA layers a read against 9; `auto` takes two) and read from its nearest mip level or
# trilinearly (`auto`: nearest on a CPU device, trilinear on a GPU, which was not measured when that was chosen).
size=${frames[0]} w=${size%x*} h=${size#*x}
"$bin" profile "${device_args[@]}" --width "$w" --height "$h" --frames "$scene_frames" --warmup "$scene_warmup" \
  --no-reference --samples 1 --any-view --sweep target=display table_segments=1,2 table_mips=linear,nearest \
  --csv "$out/any-view-$size.csv" >"$out/any-view-$size.md" 2>"$out/any-view-$size.err" \
  || { echo "FAIL  timing any-view $size"; cat "$out/any-view-$size.err"; failures=$((failures + 1)); }
echo "-- default scene's any-view table at $size (the viewer's frames), by segments of w and mip filter"
sed -n '/^| configuration/,$p' "$out/any-view-$size.md"
"$bin" profile "${device_args[@]}" --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 \
  --height-um 0.375 --tile 10 --exposure 8 --frames "$map_frames" --warmup "$map_warmup" --reference-pixels 2000 \
  --roofline \
  --sweep approach=gem,baked "size=$map_sizes" --csv "$out/map.csv" >"$out/map.md" 2>"$out/map.err" \
  || { echo "FAIL  timing map"; cat "$out/map.err"; failures=$((failures + 1)); }
echo "-- Elaphe BRDF map, gem against baked"
sed -n '/^| approach/,/^$/p' "$out/map.md"
# The two pipelines a map can take (the device's default is in the table above), pass by pass.
"$bin" profile "${device_args[@]}" --heightfield assets/afm/elaphe-100px.png --pixel-size-um 0.065 \
  --height-um 0.375 --tile 10 --exposure 8 --frames "$map_frames" --warmup "$map_warmup" --no-reference \
  --sweep approach=gem,baked "size=$map_sizes" shader=fragment,compute --csv "$out/map-shader.csv" \
  >"$out/map-shader.md" 2>"$out/map-shader.err" \
  || { echo "FAIL  timing map shaders"; cat "$out/map-shader.err"; failures=$((failures + 1)); }
echo "-- Elaphe BRDF map's shading by either pipeline"
sed -n '/^| configuration/,/^$/p' "$out/map-shader.md"

echo "gpu-check: logs, CSV files and tables in $out"
if [ "$failures" -gt 0 ]; then
  echo "gpu-check: $failures check(s) failed on device $device"
  exit 1
fi
echo "gpu-check: every user path is validation-clean and $tests test binaries pass on device $device"
