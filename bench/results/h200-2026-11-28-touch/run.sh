#!/usr/bin/env bash
# Exact edges on the H200: run (26a70c8, the run of voxels let off) against
# touch (c7c58cc: zero taken as outside in the voxels, and a crossing that only
# touches a sheet of no thickness searched past, its three points in one round
# of lanes); the GPU tests.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
mkdir -p .devcarry/x && tar xJf .devcarry/pack.tar.xz -C .devcarry/x
export LD_LIBRARY_PATH=$PWD/.devcarry/x/lib
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
B=.devcarry/x/bin
nvidia-smi --query-gpu=name --format=csv,noheader
timeout 240 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"; grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1 2; do
 for sc in "chair 2" "chair 0.5" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  echo "== round $round $1 $2 voxels run"
  $B/kerf_gpu_bench_run --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  for v in run touch; do
   echo "== round $round $1 $2 exact $v"
   $B/kerf_gpu_bench_$v --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  done
 done
done > $OUT/touch.txt 2>&1
grep -c exact $OUT/touch.txt
