#!/usr/bin/env bash
# Two builds of kerf against each other on the export to a tolerance, run
# alternately (before, after, before, after) so that the shared machine's
# drift falls on both: per part, feature size and tolerance, the triangles,
# the triangles left over the tolerance and the worst sample (as kerf
# export --json reports them for the file written) and the faster of the
# two times of each build. Every run is a real `kerf export`. With
# MESH_DISTANCE=path/to/kerf_mesh_distance, each build's first file is
# also measured against the exact surface (the upper bound of the distance,
# SurfaceDistance.hpp), and its triangles facing into the part (normal more
# than 90 degrees from the gradient at the centroid: folds) are counted:
# the worst sample is each build's own judgement. The last column says
# whether the two builds wrote the same file, byte for byte.
#
#   bash bench/export-before-after.sh BEFORE_KERF AFTER_KERF [PART:FEATURE:TOLERANCE ...]
set -euo pipefail
cd "$(dirname "$0")/.."
before=$1 after=$2
shift 2
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(bench/data/plain-panel.kerf:1:0.01 bench/data/board-on-lattice.kerf:1:0.01
  resources/examples/bookshelf-side.kerf:4:0.01 resources/examples/side-chair.kerf:4:0.01
  resources/examples/table-top.kerf:4:0.01)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run() { # kerf part feature tolerance file -> "triangles over worst seconds"
  "$1" export "$2" -o "$5" --feature-size "$3" --tolerance "$4" --json 2>/dev/null |
    python3 -c 'import json,sys; j=json.load(sys.stdin); print(j["triangles"], j["triangles_over_tolerance"], "%.4f" % j["worst_sample_mm"], "%.2f" % j["seconds"])'
}
distance() { # part file -> "largest distance at a sample (upper bound, mm) triangles facing into the part"
  if [ -n "${MESH_DISTANCE:-}" ]; then
    "$MESH_DISTANCE" "$1" "$2" | python3 -c 'import json,sys; j=json.load(sys.stdin); print("%.4f" % j["distance_max_mm"], j["triangles_facing_across"])'
  else
    echo "- -"
  fi
}
echo "| part | cells mm | tolerance mm | triangles before → after | over tolerance before → after | worst sample mm before → after | distance max mm before → after | facing into the part before → after | time s before → after | same file |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
  IFS=: read -r part feature tolerance <<<"$c"
  read -r bt bo bw bs1 <<<"$(run "$before" "$part" "$feature" "$tolerance" "$out/before.stl")"
  read -r at ao aw as1 <<<"$(run "$after" "$part" "$feature" "$tolerance" "$out/after.stl")"
  read -r _ _ _ bs2 <<<"$(run "$before" "$part" "$feature" "$tolerance" "$out/part.stl")"
  read -r _ _ _ as2 <<<"$(run "$after" "$part" "$feature" "$tolerance" "$out/part.stl")"
  bs=$(python3 -c "print(min($bs1, $bs2))") as=$(python3 -c "print(min($as1, $as2))")
  read -r bd bf <<<"$(distance "$part" "$out/before.stl")"
  read -r ad af <<<"$(distance "$part" "$out/after.stl")"
  same=no
  if cmp -s "$out/before.stl" "$out/after.stl"; then same=yes; fi
  echo "| $(basename "$part" .kerf) | $feature | $tolerance | $bt → $at | $bo → $ao | $bw → $aw | $bd → $ad | $bf → $af | $bs → $as | $same |"
done
