#!/usr/bin/env bash
# Issue 13's side-by-side benchmark: Kerf's export against Manifold (the
# exact mesh-boolean library behind current OpenSCAD) on the bundled
# examples that Manifold can build exactly (no blends, offsets or shells),
# at the same tolerance, same machine, same run. Both files are measured
# by the same reader and the same distance to Kerf's exact surface
# (build/bench/kerf_mesh_distance).
#
#   bash bench/manifold/compare.sh [KERF_BUILD] [FEATURE_SIZE] [TOLERANCES...]
#   bash bench/manifold/compare.sh build 2 0.1 0.05
#
# Manifold gets the circle segments that the tolerance asks for
# (manifold-export.mjs); where its sphere or hull then still strays beyond
# the tolerance (its spheres are subdivided octahedra, not polygons of
# revolution), the script asks again with 0.7 times the tolerance, up to
# eight times, and reports the first mesh within it: Manifold as tight as
# the tolerance, never looser. Needs node and `npm install` here (one
# package: manifold-3d, pinned in package.json).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-build}
feature=${2:-2}
shift 2 || true
tolerances=("$@")
[ ${#tolerances[@]} -gt 0 ] || tolerances=(0.1 0.05)
kerf="$root/$build/bin/kerf"
measure="$root/$build/bench/kerf_mesh_distance"
[ -d "$here/node_modules/manifold-3d" ] || (cd "$here" && npm install --silent >/dev/null)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
echo "| part | tolerance mm | program | triangles | max distance mm | mean distance mm | closed | time s |"
echo "|---|---|---|---|---|---|---|---|"
for name in bookshelf-side table-top; do
  doc="$root/resources/examples/$name.kerf"
  for tolerance in "${tolerances[@]}"; do
    asked=$tolerance
    for attempt in 1 2 3 4 5 6 7 8; do
      node "$here/manifold-export.mjs" "$doc" "$asked" "$out/m.stl" >"$out/m.json"
      "$measure" "$doc" "$out/m.stl" >"$out/md.json"
      python3 -c "import json,sys; sys.exit(0 if json.load(open(sys.argv[1]))['distance_max_mm'] <= float(sys.argv[2]) else 1)" \
        "$out/md.json" "$tolerance" && break
      asked=$(python3 -c "print($asked * 0.7)")
    done
    python3 - "$name" "$tolerance" "$out/m.json" "$out/md.json" "$asked" <<'PY'
import json, sys
name, tol, built, measured, asked = sys.argv[1:]
b, m = json.load(open(built)), json.load(open(measured))
print(f"| {name} | {tol} | Manifold 3.5.4 (segments for {float(asked):.3g} mm) | {m['triangles']:,} | {m['distance_max_mm']:.3f} | "
      f"{m['distance_mean_mm']:.4f} | {'yes' if m['watertight'] and m['self_intersections'] == 0 else 'no'} | {b['seconds']:.2f} |")
PY
    start=$(date +%s.%N)
    "$kerf" export "$doc" -o "$out/k.stl" --feature-size "$feature" --tolerance "$tolerance" >/dev/null 2>"$out/k.err" || true
    end=$(date +%s.%N)
    "$measure" "$doc" "$out/k.stl" >"$out/kd.json"
    python3 - "$name" "$tolerance" "$out/kd.json" "$start" "$end" "$feature" <<'PY'
import json, sys
name, tol, measured, start, end, feature = sys.argv[1:]
m = json.load(open(measured))
print(f"| {name} | {tol} | Kerf ({feature} mm cells) | {m['triangles']:,} | {m['distance_max_mm']:.3f} | "
      f"{m['distance_mean_mm']:.4f} | {'yes' if m['watertight'] and m['self_intersections'] == 0 else 'no'} | {float(end) - float(start):.2f} |")
PY
  done
done
