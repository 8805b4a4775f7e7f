#!/usr/bin/env bash
# The whole test run (README "Set up and pass the tests", CI): after ./setup.sh has built
# build/, this
#   1. runs every test of build/ (CUDA as configured there);
#   2. builds build-asan (CUDA off, ASan + UBSan incl. float-cast-overflow, aborting on the
#      first report) and runs its tests except the long "quality" ones;
#   3. builds build-tsan (CUDA off, ThreadSanitizer) and runs the CPU backend's and the
#      stage loop's threaded tests;
#   4. compiles the GPU backend for AMD GPUs into build-hip with Debian's hipcc
#      (tests/gpu/compile_hip.sh: installs hipcc when missing) and runs it without a GPU.
# It runs every part, prints each part's time and fails when any part failed.
# Usage: tests/run_all.sh [--no-sanitizers]  (only part 1)
# MPMVS_RUN_WRAPPER, when set, prefixes every build and ctest command (e.g. "flock FILE" to
# share a machine with other builds).
set -uo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
sanitizers=1
if [ "${1:-}" = "--no-sanitizers" ]; then sanitizers=0; fi

# The threaded CPU paths: the backend's own tests and the stage loop's (without "quality").
TSAN_TESTS='^(PatchMatchCpu|KernelNcc|CudaBackend\.HostEmulated|Pipeline)\.'

failed=()
timings=()
part() {  # part NAME COMMAND...: runs the command, records its time and failure
  local name=$1
  shift
  echo "==== run_all: ${name}"
  local start=$SECONDS
  if ! "$@"; then failed+=("$name"); fi
  timings+=("${name}: $((SECONDS - start)) s")
}

run() {  # run COMMAND...: with the wrapper
  # shellcheck disable=SC2086
  ${MPMVS_RUN_WRAPPER:-} "$@"
}

sanitizer_build() {  # sanitizer_build DIR SANITIZER
  if [ ! -f "$1/CMakeCache.txt" ]; then
    run cmake -S . -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-g1 -DMPMVS_SANITIZE="$2" \
      -DMPMVS_ENABLE_CUDA=OFF -DMPMVS_BUILD_BENCHMARKS=OFF -DMPMVS_WITH_COLMAP=OFF > /dev/null || return 1
  fi
  run cmake --build "$1" -j "$jobs"
}

# A sanitizer report aborts the test (and any colmap-mp it starts) with a clear stack.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}

part "tests (build)" run ctest --test-dir build --output-on-failure
if [ "$sanitizers" = 1 ]; then
  part "ASan+UBSan build (build-asan)" sanitizer_build build-asan address
  # ThreadCreationFailureIsAClearError limits the address space (ulimit -v), which leaves
  # no room for ASan's shadow memory.
  part "ASan+UBSan tests (build-asan, -LE quality)" \
    run ctest --test-dir build-asan --output-on-failure -j "$jobs" -LE 'quality|slurm' -E 'ThreadCreationFailureIsAClearError'
  part "TSan build (build-tsan)" sanitizer_build build-tsan thread
  # No address randomisation: TSan's fixed shadow layout clashes with high mmap entropy.
  part "TSan tests (build-tsan, CPU backend)" \
    run setarch "$(uname -m)" -R ctest --test-dir build-tsan --output-on-failure -j "$jobs" -R "$TSAN_TESTS" -LE quality
  part "HIP build for AMD GPUs (build-hip)" run tests/gpu/compile_hip.sh build-hip
fi

echo "==== run_all: times"
printf '  %s\n' "${timings[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  printf 'run_all: FAILED: %s\n' "${failed[@]}"
  exit 1
fi
echo "run_all: all parts passed"
