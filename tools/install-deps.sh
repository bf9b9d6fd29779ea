#!/usr/bin/env bash
# Installs every Debian 12 package that Kerf's build, program and tests need.
# Idempotent and quiet: packages already present are not fetched again, and the
# package lists are refreshed only when something is actually missing.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git
  # core
  nlohmann-json3-dev libtbb-dev libglm-dev libopenmesh-dev libstb-dev
  # 3MF export (lib3mf) and the files its pkg-config names (libzip, zlib)
  lib3mf-dev libzip-dev zlib1g-dev
  # the 3MF file's UUIDs drawn from its content (xxHash, used header-only)
  libxxhash-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # the fuzzer and the ThreadSanitizer build (tools/fuzz.sh, tools/tsan.sh):
  # clang with libFuzzer, llvm-symbolizer and llvm-cov
  clang libclang-rt-14-dev llvm
  # viewport
  libvulkan-dev glslang-dev glslang-tools spirv-tools mesa-vulkan-drivers
  vulkan-tools vulkan-validationlayers
  # desktop application and its tests
  qt6-base-dev qt6-base-dev-tools libqt6opengl6-dev libqt6openglwidgets6
  qt6-charts-dev libxkbcommon-dev xvfb xauth
  # kerf bench --plot draws its text offscreen with this font
  fonts-dejavu-core
  # packaging
  dpkg-dev fakeroot lintian help2man librsvg2-bin desktop-file-utils shared-mime-info
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
