#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) into build-fuzz and runs each reader's
# fuzzer for RUNS executions (default 1,000,000), one at a time at low priority, starting
# from tests/fuzz/corpus/<reader> (seeded by mpmvs_fuzz_seeds when empty). New inputs are
# merged back into that corpus (-merge=1 keeps only inputs that add coverage); a crashing
# input lands in build-fuzz/crashes/<reader>/ and stops that reader: copy it to
# tests/fuzz/crashes/<reader>/ (replayed by tests/fuzz/fuzz_replay_test.cc) and fix the reader.
# Usage: tests/fuzz/run_fuzzers.sh [reader...]   (default: every tests/fuzz/*_fuzzer.cc)
# TIMEOUT (s, default 30): a single input slower than this is a finding (on a loaded machine
# 10 s gave false timeouts).
set -euo pipefail
cd "$(dirname "$0")/../.."
RUNS=${RUNS:-1000000}
MAX_LEN=${MAX_LEN:-4096}

if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DMPMVS_FUZZ=ON \
    -DMPMVS_ENABLE_CUDA=OFF -DMPMVS_BUILD_TESTS=OFF -DMPMVS_BUILD_BENCHMARKS=OFF -DMPMVS_WITH_COLMAP=OFF
fi
cmake --build build-fuzz --target mpmvs_fuzzers -j "$(nproc)"

readers=("$@")
if [ ${#readers[@]} -eq 0 ]; then
  for f in tests/fuzz/*_fuzzer.cc; do readers+=("$(basename "$f" _fuzzer.cc)"); done
fi
# Scratch files of the harnesses: memory is faster than disk.
if [ -d /dev/shm ]; then export TMPDIR=/dev/shm; fi

status=0
for r in "${readers[@]}"; do
  corpus=tests/fuzz/corpus/$r
  work=build-fuzz/runs/$r
  mkdir -p "$corpus" "$work" "build-fuzz/crashes/$r"
  if [ -z "$(ls -A "$corpus")" ]; then
    build-fuzz/tests/fuzz/mpmvs_fuzz_seeds build-fuzz/seeds
    cp build-fuzz/seeds/"$r"/* "$corpus"/
  fi
  dict=()
  if [ -f "tests/fuzz/$r.dict" ]; then dict=(-dict="tests/fuzz/$r.dict"); fi
  log=build-fuzz/$r.log
  start=$(date +%s)
  if nice -n 10 "build-fuzz/tests/fuzz/${r}_fuzzer" -runs="$RUNS" -max_len="$MAX_LEN" -timeout="${TIMEOUT:-30}" \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="build-fuzz/crashes/$r/" "${dict[@]}" \
      "$work" "$corpus" > "$log" 2>&1; then
    result=ok
  else
    result="FINDING (see $log, build-fuzz/crashes/$r/)"
    status=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  # Keep only the inputs that add coverage.
  rm -rf "build-fuzz/merged/$r" && mkdir -p "build-fuzz/merged/$r"
  "build-fuzz/tests/fuzz/${r}_fuzzer" -merge=1 -max_len="$MAX_LEN" "build-fuzz/merged/$r" "$corpus" "$work" \
    > "build-fuzz/$r.merge.log" 2>&1 || true
  if [ -n "$(ls -A "build-fuzz/merged/$r")" ]; then
    rm -f "$corpus"/* && cp "build-fuzz/merged/$r"/* "$corpus"/
  fi
  echo "$r: $execs executions in $(( $(date +%s) - start )) s, corpus $(ls "$corpus" | wc -l) files: $result" \
    | tee -a build-fuzz/fuzz_summary.txt
done
exit $status
