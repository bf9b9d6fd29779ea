#!/usr/bin/env bash
# Issue 13's side-by-side benchmark on the blended examples (smooth unions,
# offsets), where Manifold has no exact mesh boolean (manifold-export.mjs
# refuses them) and can only fall back to a level set: Manifold.levelSet
# of Kerf's own exact field (levelset.mjs, through tape.mjs, the JavaScript
# port of Kerf's double-precision evaluator, checked here against Kerf's
# samples first) at edge lengths 4, 2, 1 and 0.5 mm, against Kerf's own
# export at each tolerance, same machine, same run. Every file is measured
# by the same reader and the same distance to Kerf's exact surface
# (KERF_BUILD/bench/kerf_mesh_distance), as in compare.sh.
#
#   bash bench/manifold/compare-blended.sh [KERF_BUILD] [TOLERANCES...]
#   bash bench/manifold/compare-blended.sh build 0.1 0.05
#
# Manifold evaluates the field at every point of a dense grid (two cubic
# lattices), one JavaScript call each, and allocates 8 bytes per point in a
# 4 GB WebAssembly heap; halving the edge is 8 times the work. A level set
# is skipped (and the table says so) when the grid would not fit in 3 GB,
# or when the time of the previous, coarser grid scaled by the number of
# grid points comes to more than MANIFOLD_BUDGET_S seconds (default 600).
# A level set that fails inside Manifold is reported as failed. Manifold's
# time is the level set and its mesh (not the WebAssembly start or the
# writing); Kerf's is the wall time of `kerf export` at the document's own
# feature size. "Within the tolerance" (the lines after the table) is by
# the measure's upper bound, as in compare.sh. Needs node and `npm
# install` here (one package: manifold-3d, pinned in package.json), and
# KERF_BUILD's kerf, bench/kerf_mesh_distance and bench/kerf_tape_json.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-build}
shift || true
tolerances=("$@")
[ ${#tolerances[@]} -gt 0 ] || tolerances=(0.1 0.05)
edges=(4 2 1 0.5)
budget=${MANIFOLD_BUDGET_S:-600}
max_bytes=3000000000
kerf="$root/$build/bin/kerf"
measure="$root/$build/bench/kerf_mesh_distance"
tapejson="$root/$build/bench/kerf_tape_json"
[ -d "$here/node_modules/manifold-3d" ] || (cd "$here" && npm install --silent >/dev/null)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
: >"$out/rows.tsv"
: >"$out/notes"

# One table row from kerf_mesh_distance's JSON; also kept in rows.tsv
# (part, what, setting, triangles, max, max lower bound) for the fractions
# below. The max distance is the measure's upper bound, with its lower
# bound (the largest |f| at a sample) in brackets where they differ: the
# true largest distance lies between the two. They differ where the field
# is only a bound of the distance (near CSG creases, in blends, where its
# gradient is shorter than 1).
row() { # part what setting label measured.json seconds
  python3 - "$@" "$out/rows.tsv" <<'PY'
import json, sys
part, what, setting, label, measured, seconds, rows = sys.argv[1:]
m = json.load(open(measured))
closed = "yes" if m["watertight"] and m["self_intersections"] == 0 else \
         "no: not watertight" if not m["watertight"] else f"no: {m['self_intersections']:,} crossing pairs"
hi, lo = m["distance_max_mm"], m["distance_max_lower_bound_mm"]
dmax = f"{hi:.3f}" if f"{hi:.3f}" == f"{lo:.3f}" else f"{hi:.3f} (>= {lo:.3f})"
print(f"| {part} | {label} | {m['triangles']:,} | {dmax} | {m['distance_mean_mm']:.4f} | "
      f"{closed} | {float(seconds):.1f} |")
with open(rows, "a") as f:
    f.write(f"{part}\t{what}\t{setting}\t{m['triangles']}\t{hi}\t{lo}\n")
PY
}
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }

echo "| part | program | triangles | max distance mm | mean distance mm | closed | time s |"
echo "|---|---|---|---|---|---|---|"
for name in side-chair stool door-frame; do
  doc="$root/resources/examples/$name.kerf"
  "$tapejson" "$doc" --samples 20000 >"$out/$name.tape.json"
  if ! node "$here/tape.mjs" check "$out/$name.tape.json" >"$out/check.json"; then
    echo "tape.mjs disagrees with Kerf's evaluator on $name: $(cat "$out/check.json")" >&2
    exit 1
  fi
  echo "- $name: JavaScript field against Kerf's double evaluator, max |difference| $(field "$out/check.json" max_abs_difference_mm) mm over $(field "$out/check.json" samples) samples" >>"$out/notes"
  previous_seconds= previous_voxels=
  for edge in "${edges[@]}"; do
    label="Manifold 3.5.4 level set at $edge mm"
    node "$here/levelset.mjs" "$out/$name.tape.json" "$edge" --estimate >"$out/estimate.json"
    voxels=$(field "$out/estimate.json" voxels)
    grid=$(python3 -c "import json,sys; print(' x '.join(map(str, json.load(open(sys.argv[1]))['grid'])))" "$out/estimate.json")
    skip=$(python3 - "$voxels" "$max_bytes" "$budget" "${previous_seconds:-0}" "${previous_voxels:-0}" <<'PY'
import sys
voxels, max_bytes, budget, prev_s, prev_v = map(float, sys.argv[1:])
if 8 * voxels > max_bytes:
    print(f"its grid needs {8 * voxels / 1e9:.1f} GB of the 4 GB WebAssembly heap")
elif prev_v > 0 and prev_s * voxels / prev_v > budget:
    print(f"about {prev_s * voxels / prev_v / 60:.0f} min by the {prev_s:.0f} s of the coarser grid")
PY
)
    if [ -n "$skip" ]; then
      echo "| $name | $label | skipped: $skip ($grid points) ||||||"
      echo "- $name, $edge mm level set skipped: $skip (grid $grid x 2 lattices)" >>"$out/notes"
      continue
    fi
    if ! node "$here/levelset.mjs" "$out/$name.tape.json" "$edge" "$out/m.stl" >"$out/m.json" 2>"$out/m.err"; then
      echo "| $name | $label | failed: $(grep -m1 -o '[A-Za-z]*Error.*' "$out/m.err" | head -c 200 | tr '|' ' ') ||||||"
      echo "- $name, $edge mm level set failed inside Manifold: $(grep -m1 -o '[A-Za-z]*Error.*' "$out/m.err" | head -c 200) (grid $grid x 2 lattices)" >>"$out/notes"
      continue
    fi
    "$measure" "$doc" "$out/m.stl" >"$out/md.json"
    previous_seconds=$(field "$out/m.json" seconds)
    previous_voxels=$voxels
    row "$name" manifold "$edge" "$label" "$out/md.json" "$previous_seconds"
    echo "- $name, $edge mm level set: grid $grid x 2 lattices, $(python3 -c "print(f'{$(field "$out/m.json" evaluations):,}')") field evaluations, $(printf %.1f "$previous_seconds") s, Manifold's genus $(field "$out/m.json" genus)" >>"$out/notes"
  done
  for tolerance in "${tolerances[@]}"; do
    label="Kerf at tolerance $tolerance mm"
    start=$(date +%s.%N)
    if ! "$kerf" export "$doc" -o "$out/k.stl" --tolerance "$tolerance" >/dev/null 2>"$out/k.err"; then
      echo "| $name | $label | failed: $(head -c 200 "$out/k.err" | tr '\n|' '  ') ||||||"
      continue
    fi
    end=$(date +%s.%N)
    "$measure" "$doc" "$out/k.stl" >"$out/kd.json"
    row "$name" kerf "$tolerance" "$label" "$out/kd.json" "$(python3 -c "print($end - $start)")"
  done
done

echo
python3 - "$out/rows.tsv" <<'PY'
import sys
rows = [line.rstrip("\n").split("\t") for line in open(sys.argv[1]) if line.strip()]
parts = list(dict.fromkeys(r[0] for r in rows))
for part in parts:
    manifold = [(float(r[2]), int(r[3]), float(r[4])) for r in rows if r[0] == part and r[1] == "manifold"]
    for _, _, tol, tris, dmax, dlow in [r for r in rows if r[0] == part and r[1] == "kerf"]:
        tol, tris, dmax, dlow = float(tol), int(tris), float(dmax), float(dlow)
        over = "" if dmax <= tol else \
            f" (Kerf's own mesh measures {dmax:.3f} mm, over the tolerance by the upper bound only: |f| at most {dlow:.3f} mm)" \
            if dlow <= tol else f" (Kerf's own mesh is over the tolerance: {dlow:.3f} to {dmax:.3f} mm)"
        within = [m for m in manifold if m[2] <= tol]
        if within:
            edge, mtris, mmax = min(within, key=lambda m: m[1])
            print(f"- {part} at {tol:g} mm: Kerf's {tris:,} triangles are {tris / mtris:.3f} of the smallest "
                  f"Manifold level set within the tolerance ({edge:g} mm edges: {mtris:,} triangles, "
                  f"{mmax:.3f} mm){over}")
        elif manifold:
            edge, mtris, mmax = min(manifold, key=lambda m: m[0])
            print(f"- {part} at {tol:g} mm: no Manifold level set measured is within the tolerance; Kerf's "
                  f"{tris:,} triangles are {tris / mtris:.3f} of the finest one ({edge:g} mm edges: {mtris:,} "
                  f"triangles, {mmax:.3f} mm){over}")
PY
echo
cat "$out/notes"
