#!/usr/bin/env bash
# Exact edges on the H200: v0 (HEAD 58fc75f..: one voxel before the hit let
# off), run (every voxel of a run closing in on the hit's sheet let off),
# run16 (the same with 16 lanes a ray instead of 32); the GPU tests.
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
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  echo "== round $round $1 $2 voxels v0"
  $B/kerf_gpu_bench_v0 --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  for v in v0 run run16; do
   echo "== round $round $1 $2 exact $v"
   $B/kerf_gpu_bench_$v --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  done
 done
done > $OUT/let-off.txt 2>&1
grep -c exact $OUT/let-off.txt
