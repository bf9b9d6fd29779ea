#!/usr/bin/env bash
# Exact edges with the listed pass's tile tape held in shared memory (each ray
# its own slot): kerf_gpu_bench_before (637d95f) against
# kerf_gpu_bench (this change), the voxels from the latter, alternated twice
# in one run; then the GPU tests; first, the compiler's statistics of every
# trace pipeline before (kerf_gpu_bench_head_stats: 637d95f's shader with
# --pipeline-statistics) and after. Run from the device tool with .gl and
# .devcarry/pack.tar.xz (kerf_gpu_bench, kerf_gpu_bench_before,
# kerf_viewport_tests and their libraries) carried.
set -u
source bench/device-env.sh
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
for v in head_stats after; do
 bin=$B/kerf_gpu_bench; [ $v = head_stats ] && bin=$B/kerf_gpu_bench_head_stats
 echo "== $v"; timeout 60 $bin --scene chair --feature-size 2 --quality all --frames 2 --pipeline-statistics | grep -v "^scene"
done > $OUT/pipeline-statistics.txt 2>&1
grep -c pipeline $OUT/pipeline-statistics.txt
for round in 1 2; do
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1"; do
  set -- $sc
  echo "== round $round $1 $2 voxels after"
  timeout 60 $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  for v in before after; do
   bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
   echo "== round $round $1 $2 exact $v"
   timeout 60 $bin --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  done
 done
done > $OUT/staged-tapes.txt 2>&1
grep -c exact $OUT/staged-tapes.txt
timeout 240 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
