#!/usr/bin/env bash
# Builds Kerf and runs it on the bundled example part (the side chair): the
# desktop application when there is a display; without one, the headless
# commands on the same part (check, render to build/side-chair.png, export
# to build/side-chair.stl).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
[ -f build/CMakeCache.txt ] || cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target kerf
example=resources/examples/side-chair.kerf
# A private runtime folder keeps Mesa's shader cache and warnings quiet.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="$(mktemp -d)"
  chmod 700 "$XDG_RUNTIME_DIR"
fi
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec build/bin/kerf "$example" "$@"
fi
echo "run-example: no display here; running kerf headless on $example" >&2
build/bin/kerf check "$example"
build/bin/kerf render "$example" -o build/side-chair.png "$@"
build/bin/kerf export "$example" -o build/side-chair.stl --feature-size 2
echo "run-example: wrote build/side-chair.png and build/side-chair.stl; with a display, this opens the application" >&2
