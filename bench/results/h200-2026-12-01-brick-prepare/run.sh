#!/usr/bin/env bash
# The brick atlases' upload on the H200, before (a7301d2^: the staging
# memory made in the first frame of the upload) and after (made beforehand,
# BrickRenderer::prepare), alternated in one run; the brick renderer's GPU
# tests first. Run from the device tool with .gl and .devcarry/pack.tar.xz
# (kerf_before, kerf, kerf_viewport_tests and their libraries) carried.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export QT_QPA_PLATFORM=offscreen XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p .devcarry/x && tar xJf .devcarry/pack.tar.xz -C .devcarry/x
export LD_LIBRARY_PATH=$PWD/.devcarry/x/lib
B=.devcarry/x/bin
nvidia-smi --query-gpu=name --format=csv,noheader
[ -n "${SKIP_TESTS:-}" ] || timeout 240 $B/kerf_viewport_tests --gtest_filter='*Brick*' > $OUT/tests.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1 2; do
  for b in kerf_before kerf; do
    echo "== round $round $b"
    timeout 200 $B/$b bench resources/examples/side-chair.kerf --feature-sizes 1,0.5,0.25 --size 1920x1080 \
      --frames 3 --trace-only --bricks --json $OUT/$b-$round.json 2>&1 | tail -3
  done
done > $OUT/bench.txt 2>&1
tail -20 $OUT/bench.txt
