#!/usr/bin/env bash
# (Dropped, docs/benchmarks.md "The check joined to the voxel pass": run from
# a working tree that had the joined pass and KERF_TRACE_SEPARATE_CHECK.)
# Exact edges on the H200: the check of the voxel hits joined to the voxel
# pass (two dispatches) against the check in a dispatch of its own
# (KERF_TRACE_SEPARATE_CHECK=1, three dispatches, as before), alternated in
# one run; the voxel trace beside them; the GPU tests first.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
mkdir -p .devcarry/x && tar xJf .devcarry/pack.tar.xz -C .devcarry/x
export LD_LIBRARY_PATH=$PWD/.devcarry/x/lib
mkdir -p /work/main && ln -sfn $PWD/resources /work/main/resources
B=.devcarry/x/bin
nvidia-smi --query-gpu=name --format=csv,noheader
timeout 200 $B/kerf_viewport_tests > $OUT/tests.txt 2>&1; echo "tests rc=$?"; grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1 2; do
 for sc in "chair 2" "chair 1" "chair 0.5" "chair 0.25" "showcase 0.1" "showcase 0.01"; do
  set -- $sc
  echo "== round $round $1 $2 voxels"
  $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality voxels --frames 20 | grep -v "^scene\|^device"
  echo "== round $round $1 $2 exact fused"
  $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
  echo "== round $round $1 $2 exact separate"
  KERF_TRACE_SEPARATE_CHECK=1 $B/kerf_gpu_bench --scene $1 --feature-size $2 --quality exact --frames 20 | grep -v "^scene\|^device"
 done
done > $OUT/fused.txt 2>&1
grep -c exact $OUT/fused.txt
