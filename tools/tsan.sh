#!/usr/bin/env bash
# Runs the test suite under ThreadSanitizer: the voxelizer's and the mesher's
# oneTBB tasks, the background voxelizer and its occlusion loop, the voxel
# streamer, the viewport's render thread and the application's threads (the
# UI tests run the real window under Xvfb).
#
#   bash tools/tsan.sh                 build-tsan/, then ctest (every test)
#   bash tools/tsan.sh -R Voxel        only the tests ctest -R selects
#
# Debian's oneTBB is not instrumented: TSan cannot see its synchronization
# and reports thousands of false races inside every parallel_for. This
# script therefore builds oneTBB from Debian's own source package (the very
# version libtbb-dev installs) with -fsanitize=thread, once, into
# .cache/tbb-tsan/VERSION (gitignored), and builds Kerf against it in
# build-tsan/ (clang, -fsanitize=thread, -O1 -g). Qt and Mesa stay
# uninstrumented; tools/tsan.supp lists the few reports that come from inside
# them, each with the reason. TSan stops at the first report
# (halt_on_error=1): a clean run is a run where every test passes.
set -euo pipefail
cd "$(dirname "$0")/.."

bash tools/install-deps.sh

version=$(dpkg-query -W -f='${Version}' libtbb-dev)
cache=.cache/tbb-tsan
prefix="$PWD/$cache/$version"
if [ ! -f "$prefix/lib/cmake/TBB/TBBConfig.cmake" ]; then
  mkdir -p "$cache"
  # Source packages need deb-src entries; add Debian's if there are none.
  if ! apt-cache showsrc onetbb >/dev/null 2>&1 || [ -z "$(apt-cache showsrc onetbb 2>/dev/null)" ]; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    echo "tsan.sh: adding Debian's deb-src entries (/etc/apt/sources.list.d/kerf-deb-src.sources)" >&2
    $SUDO tee /etc/apt/sources.list.d/kerf-deb-src.sources >/dev/null <<'EOF'
# Added by kerf's tools/tsan.sh: Debian's source packages (oneTBB is rebuilt
# with ThreadSanitizer from its source package).
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb-src
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    $SUDO apt-get update -qq
  fi
  rm -rf "$cache/src" "$cache/build"
  mkdir -p "$cache/src"
  (cd "$cache/src" && apt-get source -qq "onetbb=$version" >/dev/null)
  source_dir=$(find "$cache/src" -mindepth 1 -maxdepth 1 -type d -name 'onetbb-*' | head -1)
  CC=clang CXX=clang++ cmake -S "$source_dir" -B "$cache/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBBMALLOC_BUILD=OFF -DTBB_STRICT=OFF \
    -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
  cmake --build "$cache/build"
  cmake --install "$cache/build" >/dev/null
  rm -rf "$cache/src" "$cache/build"
fi

build=build-tsan
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKERF_TSAN=ON \
    -DKERF_BUILD_BENCH=OFF -DCMAKE_PREFIX_PATH="$prefix" -DTBB_DIR="$prefix/lib/cmake/TBB" >/dev/null
fi
cmake --build "$build" -j "$(nproc)"

# second_deadlock_stack: both stacks of a lock-order inversion;
# history_size: longer memory for the other access of a race;
# report_destroy_locked=0: at exit, QApplication's destructor closes the X
# display and libxcb destroys its connection mutex locked (inside xcb,
# uninstrumented); TSan 14 then hangs while writing that report (the
# ui.cpuFallback tests ran into ctest's 30-minute timeout, stuck in
# ReportDestroyLocked under XCloseDisplay). A suppression cannot help: the
# hang comes before suppressions are matched.
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 history_size=4 report_destroy_locked=0 suppressions=$PWD/tools/tsan.supp ${TSAN_OPTIONS:-}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
chmod 700 "$XDG_RUNTIME_DIR" 2>/dev/null || true
cd "$build"
ctest -j "$(nproc)" --output-on-failure --timeout 1800 "$@"
