#!/usr/bin/env bash
# Bricks wholly on a section's cut side culled in brick.vert: the brick
# renderer's GPU tests, then kerf_gpu_bench bricks before (53eeb2b) and after,
# alternated twice in one run. Run from the device tool with .gl and
# .devcarry/pack.tar.xz (kerf_gpu_bench, kerf_gpu_bench_before,
# kerf_viewport_tests and their libraries) carried.
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
for round in 1 2; do
  for v in before after; do
    bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
    timeout 200 $bin bricks --examples resources/examples --frames 20 --accuracy-width 0 \
      --json $OUT/bricks-$v-$round.json > $OUT/bench-$v-$round.txt 2>&1; echo "$v $round rc=$?"
  done
done
grep -h "section" $OUT/bench-*.txt | head -0
for f in $OUT/bench-*.txt; do echo "== $f"; grep -E "^(chair|showcase)|section" $f; done
