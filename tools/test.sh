#!/usr/bin/env bash
# Builds Kerf and runs the whole test suite; ends with ctest's summary.
#   bash tools/test.sh              Release build in build/
#   bash tools/test.sh --sanitize   Debug + AddressSanitizer/UndefinedBehaviorSanitizer in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
cmake_args=(-DCMAKE_BUILD_TYPE=Release)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  cmake_args=(-DCMAKE_BUILD_TYPE=Debug -DKERF_SANITIZE=ON -DKERF_BUILD_BENCH=OFF)
fi
# Warnings are errors in CI (CI=true), warnings elsewhere.
if [ "${CI:-}" = "true" ]; then cmake_args+=(-DKERF_WERROR=ON); fi

bash tools/install-deps.sh

# Compiler cache keyed by paths relative to the checkout, so that a fresh
# clone elsewhere (CI's) finds what an earlier build compiled (with absolute
# paths it found about 1% on 2026-12-01).
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"

generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" "${generator[@]}" "${cmake_args[@]}" >/dev/null
else
  cmake -S . -B "$build_dir" "${cmake_args[@]}" >/dev/null
fi
cmake --build "$build_dir" -j "$(nproc)"

export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Leaks inside lib3mf's 3MF reader, used by the tests only (the file says why).
export LSAN_OPTIONS="suppressions=$PWD/tools/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
# Vulkan (Mesa) wants a private runtime folder and a writable shader cache.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
chmod 700 "$XDG_RUNTIME_DIR" 2>/dev/null || true
cd "$build_dir"
ctest -j "$(nproc)" --output-on-failure --timeout 900
