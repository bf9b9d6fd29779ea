#!/usr/bin/env bash
# The checks of the written file before (0182e3e) and after (c4f9190), same
# run, builds alternated: `kerf export PART -o OUT --json` on dev-2c.
# Usage: run.sh BEFORE_KERF AFTER_KERF > raw.txt
set -u
before=$1 after=$2
ex=/work/main/resources/examples
out=$(mktemp -d)
run() { # label binary args...
  local label=$1 bin=$2; shift 2
  /usr/bin/time -f "%M" -o "$out/mem" "$bin" export "$@" --json > "$out/j" 2> "$out/err"
  local rc=$?
  python3 - "$label" "$rc" "$out/j" "$out/mem" <<'PY'
import json, sys
label, rc, jf, mf = sys.argv[1:]
d = json.load(open(jf)) if rc == "0" else {}
mem = open(mf).read().split()[-1]
print(label, "rc", rc, "triangles", d.get("triangles"), "closed", d.get("closed"), "self", d.get("self_intersections"),
      "seconds %.2f" % d.get("seconds", -1), "lattice %.2f" % d.get("lattice_seconds", -1), "peak_MB %.0f" % (int(mem) / 1024))
PY
  md5sum "${@:3:1}" 2>/dev/null | cut -c1-12 | sed "s/^/$label md5 /"
}
for round in 1 2; do
  for build in before after; do
    bin=${!build}
    run "$round $build chair-0.5-raw" "$bin" $ex/side-chair.kerf -o "$out/a.stl" --tolerance 0
    run "$round $build chair-1-raw" "$bin" $ex/side-chair.kerf -o "$out/a.stl" --tolerance 0 --feature-size 1
    run "$round $build chair-1-raw-3mf" "$bin" $ex/side-chair.kerf -o "$out/a.3mf" --tolerance 0 --feature-size 1
    run "$round $build bookshelf-raw" "$bin" $ex/bookshelf-side.kerf -o "$out/a.stl" --tolerance 0
    run "$round $build stool-raw" "$bin" $ex/stool.kerf -o "$out/a.stl" --tolerance 0
    run "$round $build chair-default" "$bin" $ex/side-chair.kerf -o "$out/a.stl"
  done
done
rm -rf "$out"
