#!/usr/bin/env bash
# The check folded into the voxel pass (fused) against two passes (new: 18e4ccb), H100; the GPU tests.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/.devcarry/lib
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
B=.devcarry/bin
nvidia-smi --query-gpu=name --format=csv,noheader
timeout 100 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"; grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1; do
 for sc in "chair 2" "chair 0.5" "chair 0.25" "showcase 0.1"; do
  set -- $sc
  echo "== round $round $1 $2 voxels(v0)"
  $B/kerf_gpu_bench_v0 --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  for v in new fused; do
   echo "== round $round $1 $2 exact $v"
   $B/kerf_gpu_bench_$v --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  done
 done
done 2>&1 > $OUT/fused.txt
grep -c exact $OUT/fused.txt
