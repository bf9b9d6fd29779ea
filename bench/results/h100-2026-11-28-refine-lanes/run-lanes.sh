#!/usr/bin/env bash
# Exact refinement on the H100: serial (v0: a9e3567) against lanes a ray (new: 32 on NVIDIA); the GPU tests.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/.devcarry/lib
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
B=.devcarry/bin
nvidia-smi --query-gpu=name --format=csv,noheader
timeout 200 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"; grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1 2; do
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  echo "== round $round $1 $2 voxels(v0)"
  $B/kerf_gpu_bench_v0 --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  for v in v0 new; do
   echo "== round $round $1 $2 exact $v"
   $B/kerf_gpu_bench_$v --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  done
 done
done 2>&1 > $OUT/lanes.txt
grep -c exact $OUT/lanes.txt
