#!/usr/bin/env bash
# ctest CheckOnDevice.WithoutGpuSaysSoInOneLine: on a machine without a usable NVIDIA GPU,
# tests/gpu/check_on_device.sh OUT prints exactly one line, beginning "no GPU:", and exits 77
# before configuring, building or writing anything (neither OUT nor the build folder appears).
# Where check_on_device.sh --probe finds a device, this test skips (exit 77, ctest's
# SKIP_RETURN_CODE) instead of running the whole check: run that by hand there.
set -u
script=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/check_on_device.sh

probe=$("$script" --probe 2>&1)
probe_rc=$?
if [ $probe_rc -eq 0 ]; then
  echo "skipped: a GPU is present ($probe); run tests/gpu/check_on_device.sh OUT instead"
  exit 77
fi
fail() {
  echo "FAIL: $*"
  exit 1
}
[ $probe_rc -eq 77 ] || fail "check_on_device.sh --probe exited $probe_rc, not 0 or 77: $probe"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
MPMVS_GPU_BUILD_DIR="$tmp/build-gpu" "$script" "$tmp/out" > "$tmp/output" 2>&1
rc=$?
echo "check_on_device.sh exited $rc and printed:"
cat "$tmp/output"
[ $rc -eq 77 ] || fail "exit status $rc, expected 77"
lines=$(wc -l < "$tmp/output")
[ "$lines" -eq 1 ] || fail "$lines lines of output, expected exactly one"
grep -Eq '^no GPU: .+' "$tmp/output" || fail "the line does not begin with 'no GPU: ' and a reason"
[ ! -e "$tmp/out" ] || fail "OUT was created without a GPU"
[ ! -e "$tmp/build-gpu" ] || fail "the build folder was created without a GPU"
echo "PASS"
