#!/usr/bin/env bash
# The part's side of the export's tolerance (SurfaceCoverage): every bundled
# example exported at the given tolerances, the JSON figures of both
# measures and the time the part's side takes. Usage:
#   bash bench/part-side.sh [KERF] [OUTDIR] [TOLERANCES...]
set -euo pipefail
kerf=${1:-build/bin/kerf}
out=${2:-bench/results/part-side}
shift $(( $# < 2 ? $# : 2 ))
tolerances=${*:-0.05 0.01}
mkdir -p "$out"
printf '%-15s %-5s %9s %9s %10s %9s %10s %8s %8s\n' example tol triangles worst_tri samples beyond worst_part cover_s total_s
for tol in $tolerances; do
  for f in side-chair stool door-frame bookshelf-side table-top turned-leg; do
    j="$out/$f-$tol.json"
    "$kerf" export "resources/examples/$f.kerf" -o "$out/$f.stl" --tolerance "$tol" --json > "$j" 2> "$out/$f-$tol.stderr"
    python3 - "$j" "$f" "$tol" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print('%-15s %-5s %9d %9.4f %10d %9d %10.4f %8.2f %8.2f' % (sys.argv[2], sys.argv[3], j['triangles'],
      j['worst_sample_mm'], j['part_samples'], j['part_samples_beyond_tolerance'],
      j.get('worst_part_sample_mm', 0.0), j['coverage_seconds'], j['seconds']))
PY
  done
done
rm -f "$out"/*.stl
