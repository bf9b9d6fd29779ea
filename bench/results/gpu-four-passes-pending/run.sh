#!/usr/bin/env bash
# Not yet run (no device machine was lent on 2026-12-08): exact edges in
# four passes (the voxel pass lists the check's voxel hits and the rays to
# refine; the check runs on its list alone; the exact normals of the listed
# rays in a finishing pass of their own; the voxel pass's corner-normal loop
# not unrolled) against 1b7930e, the three passes before it. Voxels and exact
# from both builds, alternated, two rounds; the compiler's statistics of each
# (the listed pass held 128 registers before); the GPU tests between the
# rounds.
#
# Binaries, built here before the call (.devcarry/bin, then packed with their
# libraries into .devcarry/pack.tar.xz as bench/device-env.sh unpacks it):
#   kerf_gpu_bench          this tree
#   kerf_viewport_tests     this tree
#   kerf_gpu_bench_before   this tree with 1b7930e's shaders/trace.comp,
#                           shaders/TraceShared.h and
#                           viewport/src/ComputeTracer.cpp checked out
#                           (git checkout 1b7930e -- those three), rebuilt,
#                           copied, then the three restored
# Run from the device tool, carrying .gl and .devcarry; the table:
#   python3 bench/results/gpu-four-passes-pending/summarize.py four-passes.txt
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
  for q in voxels exact; do
   for v in before after; do
    bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
    echo "== round $r $1 $2 $q $v"
    timeout 60 $bin --scene $1 --feature-size $2 --quality $q --frames 20 | grep -v "^scene\|^device"
   done
  done
 done
}
SECONDS=0
r=1; round > $OUT/four-passes.txt 2>&1; echo "round 1 $SECONDS s"
timeout 200 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$? $SECONDS s"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
r=2; round >> $OUT/four-passes.txt 2>&1; echo "round 2 $SECONDS s"
grep -c exact $OUT/four-passes.txt
