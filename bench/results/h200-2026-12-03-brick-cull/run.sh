#!/usr/bin/env bash
# Bricks wholly on a section's cut side culled in brick.vert: the brick
# renderer's GPU tests, then kerf_gpu_bench bricks before (53eeb2b) and after,
# alternated twice in one run. Run from the device tool with .gl and
# .devcarry/pack.tar.xz (kerf_gpu_bench, kerf_gpu_bench_before,
# kerf_viewport_tests and their libraries) carried.
set -u
source bench/device-env.sh
timeout 200 $B/kerf_viewport_tests --gtest_filter='*Brick*' > $OUT/tests.txt 2>&1; echo "tests rc=$?"
grep -E "PASSED|FAILED|Failure" $OUT/tests.txt | head
for round in 1 2; do
  for v in before after; do
    bin=$B/kerf_gpu_bench; [ $v = before ] && bin=$B/kerf_gpu_bench_before
    timeout 200 $bin bricks --examples resources/examples --frames 20 --accuracy-width 0 \
      --json $OUT/bricks-$v-$round.json > $OUT/bench-$v-$round.txt 2>&1; echo "$v $round rc=$?"
  done
done
for f in $OUT/bench-*.txt; do echo "== $f"; grep -E "^(chair|showcase)|section" $f; done
