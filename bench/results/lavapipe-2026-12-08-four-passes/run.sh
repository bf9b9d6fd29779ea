#!/usr/bin/env bash
# Exact edges in four passes (the landed change, built as
# kerf_gpu_bench_compact) against 1b7930e (kerf_gpu_bench_before) on
# lavapipe (dev-2c, 2 cores), alternated, two rounds; voxels from the
# before build (their pipeline is the same in both). The binaries as built
# for the device run (.devcarry/bin).
set -u
B=.devcarry/bin
for r in 1 2; do
 for fs in 2 0.5; do
  if [ $r = 1 ]; then
   echo "== round $r chair $fs voxels before"
   xvfb-run -a $B/kerf_gpu_bench_before --scene chair --feature-size $fs --quality voxels --frames 3 | grep -v "^scene\|^device"
  fi
  for v in before compact; do
   echo "== round $r chair $fs exact $v"
   xvfb-run -a $B/kerf_gpu_bench_$v --scene chair --feature-size $fs --quality exact --frames 3 | grep -v "^scene\|^device"
  done
 done
done
