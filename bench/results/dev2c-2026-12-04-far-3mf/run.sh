#!/usr/bin/env bash
# The bundled examples 100 m from the origin (wrapped in a union translated
# by (1e5, -1e5, 1e5)) exported as 3MF, before and after, and at the origin.
# Usage: run.sh BEFORE_KERF AFTER_KERF FAR_DIR
set -u
before=$1 after=$2 far=$3
for part in turned-leg table-top door-frame stool; do
  for tol in 0.05 0.01; do
    for build in before after origin; do
      case $build in
        before) bin=$before doc=$far/$part.kerf ;;
        after) bin=$after doc=$far/$part.kerf ;;
        origin) bin=$after doc=resources/examples/$part.kerf ;;
      esac
      $bin export $doc -o /tmp/far-out.3mf --tolerance $tol --json 2>/dev/null |
        /usr/bin/python3 -c "import json,sys; j=json.load(sys.stdin); print('$part', $tol, '$build', j['triangles'], j['triangles_over_tolerance'], '%.4f' % j['worst_sample_mm'], j['part_samples_beyond_tolerance'], j.get('file_offset_mm'), '%.2f' % j['seconds'])"
    done
  done
done
