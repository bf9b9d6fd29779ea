#!/usr/bin/env bash
# H100: the GPU voxelizer before and after the per-node tape pruning.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export LD_LIBRARY_PATH=$PWD/.devcarry/lib
B=.devcarry/bin
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm --format=csv > $OUT/gpu.txt 2>&1
# Cold and warm at 0.25 mm: before, after, after --no-prune, alternated; processes back to back.
for i in 1 2 3 4; do
  echo "=== before run $i"; $B/kerf_gpu_bench_before voxelize --no-cpu --repeats 5 --scene chair --feature-size 0.25 --examples resources/examples
  echo "=== after run $i"; $B/kerf_gpu_bench voxelize --no-cpu --repeats 5 --scene chair --feature-size 0.25 --examples resources/examples
  echo "=== after --no-prune run $i"; $B/kerf_gpu_bench voxelize --no-cpu --no-prune --repeats 5 --scene chair --feature-size 0.25 --examples resources/examples
done > $OUT/cold-025.txt 2>&1
# Every scene and size, after (GPU only: the CPU path did not change).
$B/kerf_gpu_bench voxelize --no-cpu --repeats 5 --examples resources/examples --json $OUT/vox.json > $OUT/vox.txt 2>&1
# Edits to their final picture, before and after.
for i in 1 2; do
  echo "=== before run $i"; $B/kerf_gpu_bench_before edit --edits 9 --examples resources/examples
  echo "=== after run $i"; $B/kerf_gpu_bench edit --edits 9 --examples resources/examples
done > $OUT/edit.txt 2>&1
echo done
