#!/usr/bin/env bash
# scripts/gpu-check.sh on a lent, bare GPU machine (an NVIDIA driver and its Vulkan ICD; no loader, no
# validation layer, no font, no Rust), in two steps:
#
#   scripts/lent-gpu.sh prepare        here: downloads (does not install) the Debian packages the machine lacks
#                                      into .gl/ and bundles the release binary and test binaries into
#                                      .gpu-bundle/ (both ignored by git; about 36 MB to carry)
#   scripts/lent-gpu.sh run OUT [ARGS] there, from the repository root with .gl and .gpu-bundle carried: unpacks
#                                      the loader, glvnd (NVIDIA's Vulkan driver is libGLX_nvidia.so.0) and the
#                                      font into /, the validation layer into /tmp/vl, runs gpu-check.sh with
#                                      ARGS, and leaves OUT/gpu-check.tar.gz (logs, tables, CSV; no cache)
#
# docs/performance.md ("Running the checks on another device") says what it checks and what it measured.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(libvulkan1 libglvnd0 libglx0 libgl1 libegl1 libopengl0 libgles2 vulkan-validationlayers fonts-dejavu-core)

case "${1:-}" in
  prepare)
    mkdir -p .gl /tmp/lent-gpu-apt/partial
    for ignored in /.gl/ /.gpu-bundle/; do
      grep -qxF "$ignored" .gitignore .git/info/exclude 2>/dev/null || echo "$ignored" >> .git/info/exclude
    done
    apt=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/lent-gpu-apt)
    apt-get "${apt[@]}" update -qq
    (cd .gl && rm -f ./*.deb && apt-get "${apt[@]}" download "${packages[@]}" 2>&1 | grep -v unsandboxed || true)
    for p in "${packages[@]}"; do
      ls .gl/"${p}"_*.deb >/dev/null 2>&1 || { echo "lent-gpu: could not download $p" >&2; exit 2; }
    done
    scripts/gpu-check.sh --bundle .gpu-bundle
    echo "lent-gpu: carry .gl and .gpu-bundle; there, run: scripts/lent-gpu.sh run OUT"
    ;;
  run)
    out=${2:?usage: scripts/lent-gpu.sh run OUT [gpu-check options]}
    shift 2
    [ -d .gl ] && [ -x .gpu-bundle/target/release/diffract ] || {
      echo "lent-gpu: .gl or .gpu-bundle is missing: run \`scripts/lent-gpu.sh prepare\` here and carry both" >&2
      exit 2
    }
    # LENT_GPU_ROOT (default /) lets the script be tried elsewhere: a folder instead of /, and no ldconfig.
    root=${LENT_GPU_ROOT:-/}
    for deb in .gl/lib*.deb .gl/fonts-*.deb; do dpkg -x "$deb" "$root"; done
    [ "$root" != / ] || ldconfig
    mkdir -p /tmp/vl && dpkg -x .gl/vulkan-validationlayers_*.deb /tmp/vl
    export VK_LAYER_PATH=/tmp/vl/usr/share/vulkan/explicit_layer.d
    export LD_LIBRARY_PATH=/tmp/vl/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
    results=/tmp/gpu-check
    rm -rf "$results"
    status=0
    scripts/gpu-check.sh --bin-dir .gpu-bundle/target/release --out "$results" "$@" 2>&1 \
      | tee /tmp/gpu-check.log || status=$?
    mv /tmp/gpu-check.log "$results/"
    mkdir -p "$out"
    tar czf "$out/gpu-check.tar.gz" --exclude=cache --exclude=tests --exclude='*.exr' -C /tmp gpu-check
    echo "lent-gpu: results in $out/gpu-check.tar.gz"
    exit "$status"
    ;;
  *)
    sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
