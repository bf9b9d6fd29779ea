#!/usr/bin/env bash
# H100 machine: the CPU voxelizer on 1 and 16 threads, alternated, same run.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/.devcarry/lib
B=.devcarry/bin
nproc > $OUT/cpu.txt; lscpu | grep -E "Model name|Thread|Core|Socket|MHz" >> $OUT/cpu.txt
for fs in 1 0.5 0.25; do
  $B/kerf_gpu_bench voxelize --repeats 2 --scene chair --feature-size $fs --examples resources/examples --one-thread-up-to 1e9 --cpu-threads 1,16,1,16,1,16
done > $OUT/cpu-scaling.txt 2>&1
for fs in 0.1 0.01; do
  $B/kerf_gpu_bench voxelize --repeats 2 --scene showcase --feature-size $fs --examples resources/examples --one-thread-up-to 1e9 --cpu-threads 1,16,1,16,1,16
done >> $OUT/cpu-scaling.txt 2>&1
echo done
