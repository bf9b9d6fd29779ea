#!/usr/bin/env bash
# The second run: the tile walk's vectors no longer indexed by a variable and
# the voxel loops unrolled (kerf_gpu_bench), against kerf_gpu_bench_before
# (16aec24) and kerf_gpu_bench_order (the first run's build: firstCrossing
# and the list's order). Voxels from all three; exact before and with the
# list in the order listed (KERF_EXPERIMENT_LONG=0) and long stretches first
# (4); alternated twice in one run; the compiler's statistics; the GPU tests
# between the rounds. Carried as run.sh says, with kerf_gpu_bench_order too.
set -u
source bench/device-env.sh
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
timeout 60 $B/kerf_gpu_bench --scene chair --feature-size 2 --quality all --frames 2 --pipeline-statistics \
 | grep -v "^scene" > $OUT/pipeline-statistics-2.txt 2>&1
grep -c pipeline $OUT/pipeline-statistics-2.txt
round() {
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  for v in before order after; do
   bin=$B/kerf_gpu_bench; [ $v != after ] && bin=$B/kerf_gpu_bench_$v
   echo "== round $r $1 $2 voxels $v"
   timeout 60 $bin --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  done
  for v in before 0 4; do
   echo "== round $r $1 $2 exact $v"
   if [ $v = before ]; then
    timeout 60 $B/kerf_gpu_bench_before --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
   else
    KERF_EXPERIMENT_LONG=$v timeout 60 $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
   fi
  done
 done
}
r=1; round > $OUT/unindexed.txt 2>&1
timeout 200 $B/kerf_viewport_tests > $OUT/tests-2.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests-2.txt | head
r=2; round >> $OUT/unindexed.txt 2>&1
grep -c exact $OUT/unindexed.txt
