#!/usr/bin/env bash
# The brick renderer with a section plane (dcd2772) on the device machine:
# its GPU tests, then kerf_gpu_bench bricks (the compute tracer's voxel
# trace and the bricks, without and with a section across X through the
# middle, alternated twice in one run). Run from the device tool with .gl
# and .devcarry/pack.tar.xz (kerf_gpu_bench, kerf_viewport_tests and their
# libraries) carried.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p .devcarry/x && tar xJf .devcarry/pack.tar.xz -C .devcarry/x
export LD_LIBRARY_PATH=$PWD/.devcarry/x/lib
B=.devcarry/x/bin
nvidia-smi --query-gpu=name --format=csv,noheader
timeout 200 $B/kerf_viewport_tests --gtest_filter='*Brick*' > $OUT/tests.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
timeout 300 $B/kerf_gpu_bench bricks --examples resources/examples --frames 20 --accuracy-width 0 \
  --json $OUT/bricks.json > $OUT/bench.txt 2>&1; echo "bench rc=$?"
cat $OUT/bench.txt
