#!/usr/bin/env bash
# Two changes to trace.comp, measured against kerf_gpu_bench_before (16aec24):
# firstCrossing without the array indexed by a count (the voxel trace's local
# memory), and the refinement's list ordered long stretches first
# (kerf_gpu_bench; KERF_EXPERIMENT_LONG=N sets the stretch, in finest voxel
# edges, beyond which a ray goes first; 0 keeps the order listed). Voxels and
# exact from both builds, alternated twice in one run; the compiler's
# statistics before and after; the GPU tests between the rounds. Run from the
# device tool with .gl and .devcarry/pack.tar.xz (kerf_gpu_bench,
# kerf_gpu_bench_before, kerf_viewport_tests and their libraries) carried.
set -u
source bench/device-env.sh
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
for v in before after; do
 bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
 echo "== $v"; timeout 60 $bin --scene chair --feature-size 2 --quality all --frames 2 --pipeline-statistics | grep -v "^scene"
done > $OUT/pipeline-statistics.txt 2>&1
grep -c pipeline $OUT/pipeline-statistics.txt
round() {
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  for v in before after; do
   bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
   echo "== round $r $1 $2 voxels $v"
   timeout 60 $bin --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  done
  for v in before 0 2 4 8; do
   echo "== round $r $1 $2 exact $v"
   if [ $v = before ]; then
    timeout 60 $B/kerf_gpu_bench_before --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
   else
    KERF_EXPERIMENT_LONG=$v timeout 60 $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
   fi
  done
 done
}
r=1; round > $OUT/refine-order.txt 2>&1
timeout 200 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
r=2; round >> $OUT/refine-order.txt 2>&1
grep -c exact $OUT/refine-order.txt
