#!/usr/bin/env bash
# Fuzzes the document loader and everything `kerf check` does with a loaded
# document (tests/fuzz/DocumentFuzzer.cpp) with libFuzzer, ASan and UBSan.
#
#   bash tools/fuzz.sh                 120 s (the default)
#   bash tools/fuzz.sh --short         60 s: the test suite's run (ctest -L fuzz)
#   bash tools/fuzz.sh --long          one hour
#   bash tools/fuzz.sh --seconds N     N seconds
#   --timeout S                        an input taking S seconds is a finding
#                                      (default 30: the sanitized Debug build
#                                      runs about 20 times slower than Release;
#                                      raise it on a machine busy with builds)
#   bash tools/fuzz.sh --reproduce F…  runs the fuzzer's code once on each file
#   bash tools/fuzz.sh --coverage      line coverage of the corpus so far, by
#                                      file (a separate build, build-fuzz-cov/,
#                                      with clang's source-based coverage)
#
# Builds the fuzzer with clang in build-fuzz/ (Debug + ASan/UBSan, only the
# fuzzer's own target). The corpus grows in build-fuzz/corpus across runs,
# seeded from the bundled examples, the tests' documents and
# tests/fuzz/seeds; tests/fuzz/kerf.dict holds the format's keys. Findings
# (crash-*, leak-*, timeout-*, oom-*) land in build-fuzz/findings/; the script
# exits 1 when there is one. A finding's reproducer goes into
# tests/fuzz/seeds/ with a regression test once fixed.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=120
timeout=30
reproduce=()
coverage=0
while [ $# -gt 0 ]; do
  case "$1" in
    --short) seconds=60 ;;
    --long) seconds=3600 ;;
    --seconds) seconds="$2"; shift ;;
    --timeout) timeout="$2"; shift ;;
    --reproduce) shift; reproduce=("$@"); break ;;
    --coverage) coverage=1 ;;
    *) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

bash tools/install-deps.sh

if [ "$coverage" = 1 ]; then
  cov=build-fuzz-cov
  if [ ! -f "$cov/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S . -B "$cov" -G Ninja -DCMAKE_BUILD_TYPE=Release -DKERF_FUZZ=ON \
      -DKERF_BUILD_BENCH=OFF "-DCMAKE_CXX_FLAGS=-fprofile-instr-generate -fcoverage-mapping" \
      "-DCMAKE_EXE_LINKER_FLAGS=-fprofile-instr-generate" >/dev/null
  fi
  cmake --build "$cov" --target kerf_document_fuzzer -j "$(nproc)"
  rm -f "$cov"/*.profraw
  LLVM_PROFILE_FILE="$PWD/$cov/replay-%p.profraw" "$cov/tests/fuzz/kerf_document_fuzzer" -runs=0 \
    build-fuzz/corpus build-fuzz/seeds >/dev/null 2>&1 || true
  llvm-profdata merge -o "$cov/replay.profdata" "$cov"/replay-*.profraw
  llvm-cov report "$cov/tests/fuzz/kerf_document_fuzzer" -instr-profile="$cov/replay.profdata" \
    document/src evaluator/src voxelizer/src tests/fuzz
  exit 0
fi

build=build-fuzz
if [ ! -f "$build/CMakeCache.txt" ]; then
  generator=()
  if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
  CC=clang CXX=clang++ cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Debug \
    -DKERF_SANITIZE=ON -DKERF_FUZZ=ON -DKERF_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --target kerf_document_fuzzer -j "$(nproc)"
fuzzer="$build/tests/fuzz/kerf_document_fuzzer"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

if [ ${#reproduce[@]} -gt 0 ]; then
  exec "$fuzzer" -runs=1 "${reproduce[@]}"
fi

seeds="$build/seeds" corpus="$build/corpus" findings="$build/findings"
mkdir -p "$seeds" "$corpus" "$findings"
cp resources/examples/*.kerf tests/cli/data/*.kerf tests/fuzz/seeds/*.kerf "$seeds/"

# -timeout: an input that takes that long is a finding (bad input must be
# answered in seconds); -rss_limit_mb: so is one that needs 2 GB; -max_len:
# documents up to 64 KiB (the limits themselves are exercised by
# tests/HostileInputTest.cpp).
set +e
"$fuzzer" -dict=tests/fuzz/kerf.dict -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 \
  -max_len=65536 -artifact_prefix="$findings/" -print_final_stats=1 \
  "$corpus" "$seeds" 2>&1 | tee "$build/last-run.log" | grep -E "^#[0-9]+[[:space:]]+(INITED|DONE)|ERROR|SUMMARY|stat::|finding"
status=${PIPESTATUS[0]}
set -e
echo "fuzz.sh: corpus $(find "$corpus" -type f | wc -l) inputs; findings in $findings: $(find "$findings" -type f | wc -l)"
exit "$status"
