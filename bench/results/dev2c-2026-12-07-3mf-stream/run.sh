#!/usr/bin/env bash
# 3MF written in one streamed pass against sized-then-buffered (issue 13,
# 2026-12-07). /tmp/kerf-before: 47a2054; /tmp/kerf-after: the streamed
# writer. Alternated, three rounds; the files compared byte for byte.
set -u
for r in 1 2 3; do
  for k in before after; do
    /usr/bin/time -f "$k round$r chair1mm-raw.3mf %e s %M KB" /tmp/kerf-$k export resources/examples/side-chair.kerf \
      --feature-size 1 --tolerance 0 -o /tmp/m3/$k-$r.3mf 2>&1 >/dev/null | tail -1
    /usr/bin/time -f "$k round$r chair-default.3mf %e s %M KB" /tmp/kerf-$k export resources/examples/side-chair.kerf \
      -o /tmp/m3/$k-$r-d.3mf 2>&1 >/dev/null | tail -1
  done
done
for r in 1 2 3; do
  cmp /tmp/m3/before-$r.3mf /tmp/m3/after-$r.3mf && cmp /tmp/m3/before-$r-d.3mf /tmp/m3/after-$r-d.3mf && echo "round $r: same bytes"
done
