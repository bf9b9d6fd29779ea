#!/usr/bin/env bash
# Builds Kerf and runs it on the bundled example part (the side chair).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
[ -f build/CMakeCache.txt ] || cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target kerf
build/bin/kerf check resources/examples/side-chair.kerf
# A private runtime folder keeps Mesa's shader cache and warnings quiet.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
exec build/bin/kerf render resources/examples/side-chair.kerf -o build/side-chair.png "$@"
