#!/usr/bin/env bash
# The export benchmark of issue 13: every bundled example exported at each
# tolerance, on 1 and on 2 cores (taskset: oneTBB sizes its pool by the
# affinity mask), as a Markdown table: triangles, file size, worst sampled
# distance to the exact surface, triangles left over the tolerance, whether
# the simplified mesh was written (or the plain marching-cubes fallback),
# time and peak memory; with build/bench/kerf_mesh_distance built, also the
# distance of the file as read back to the exact surface (largest and mean,
# at the vertices, edge midpoints and centroids). Every run is a real
# `kerf export --json`.
#
#   bash bench/export-tolerance.sh [KERF] [FEATURE_SIZE|own] [TOLERANCES...]
#   bash bench/export-tolerance.sh build/bin/kerf 4 0 0.1 0.05
#
# Tolerance 0 is the plain marching-cubes export at the feature size
# (--tolerance 0): the baseline of the same run. FEATURE_SIZE `own`: each
# document's own (what kerf export does unless told).
set -euo pipefail
cd "$(dirname "$0")/.."
kerf=${1:-build/bin/kerf}
feature=${2:-4}
shift 2 || true
tolerances=("$@")
[ ${#tolerances[@]} -gt 0 ] || tolerances=(0 0.1 0.05)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
distance=$(dirname "$kerf")/../bench/kerf_mesh_distance
echo "| part | tolerance mm | cores | triangles | file | worst sample mm | over tolerance | simplified | distance max / mean mm | time s | peak MB |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for example in resources/examples/*.kerf; do
  name=$(basename "$example" .kerf)
  for tolerance in "${tolerances[@]}"; do
    for cores in 0 0,1; do
      args=(export "$example" -o "$out/$name.stl" --tolerance "$tolerance" --json)
      [ "$feature" = own ] || args+=(--feature-size "$feature")
      if ! /usr/bin/time -f "%M" -o "$out/rss" taskset -c "$cores" "$kerf" "${args[@]}" >"$out/json" 2>"$out/err"; then
        echo "| $name | $tolerance | $(( ${#cores} / 2 + 1 )) | failed: $(head -c 200 "$out/err" | tr '\n|' '  ') |||||||"
        continue
      fi
      echo '{}' >"$out/distance"
      if [ -x "$distance" ] && [ "$cores" = 0,1 ]; then "$distance" "$example" "$out/$name.stl" >"$out/distance" 2>/dev/null || true; fi
      python3 - "$name" "$tolerance" "$(( ${#cores} / 2 + 1 ))" "$(tail -1 "$out/rss")" "$out/json" "$out/distance" <<'PY'
import json, sys
name, tol, cores, rss, path, dpath = sys.argv[1:]
j = json.load(open(path))
d = json.load(open(dpath))
dist = f"{d['distance_max_mm']:.3f} / {d['distance_mean_mm']:.4f}" if "distance_max_mm" in d else ""
worst = j.get("worst_sample_mm")
print(f"| {name} | {tol} | {cores} | {j['triangles']:,} | {j['bytes']/1e6:.1f} MB | "
      f"{'' if worst is None else f'{worst:.3f}'} | {j['triangles_over_tolerance']} | "
      f"{'yes' if j['simplified'] and float(tol) > 0 else ('-' if float(tol) == 0 else 'no (fallback)')} | "
      f"{dist} | {j['seconds']:.2f} | {int(rss)/1024:.0f} |")
PY
    done
  done
done
