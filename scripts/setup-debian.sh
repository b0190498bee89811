#!/usr/bin/env bash
# Installs the Debian 12 packages diffract needs to build and run, when they are missing:
# lavapipe (Mesa's CPU Vulkan driver), the Vulkan loader and validation layer, shaderc's static libraries
# for build.rs, Xvfb for windows without a display, and the X11 libraries winit loads at run time.
# Safe to run again: it installs nothing when everything is present.
set -euo pipefail

packages=(
  mesa-vulkan-drivers libvulkan1 libvulkan-dev vulkan-validationlayers vulkan-tools
  libshaderc-dev glslc xvfb x11-apps imagemagick fonts-dejavu-core
  libx11-xcb1 libxkbcommon-x11-0 libxcursor1 libxrandr2 libxi6
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! command -v cargo >/dev/null 2>&1; then
  echo "setup: cargo is missing; install Rust (1.85 or newer) with rustup, then run this again" >&2
  exit 1
fi
