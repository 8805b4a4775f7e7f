#!/usr/bin/env bash
# tests/gpu/compile_hip.sh [BUILD_DIR]  (default build-hip)
#
# The GPU backend compiled for AMD GPUs: the CUDA backend's sources (kernels/*.cu) built as
# HIP by Debian's hipcc (cmake/hip_backend.cmake), as tests/run_all.sh does in CI. No AMD GPU
# is needed and none is used. Steps:
#   1. hipcc: installed from Debian's packages (hipcc, ROCm 5.2 in Debian 12) when missing.
#   2. Configure BUILD_DIR with -DMPMVS_ENABLE_HIP=ON for MPMVS_HIP_ARCHITECTURES (default
#      gfx90a); configure must print "mp-mvs: HIP backend ON (...)".
#   3. Build colmap-mp: the kernels' object (cuda_backend.cu) must carry AMD device code
#      (.hip_fatbin) and the binary must link the HIP runtime (libamdhip64).
#   4. Run it on a tiny synthetic scene: without an AMD GPU it must say "No HIP device;
#      running on the CPU" and write the maps.
# Exit 0 when every step passed, 1 otherwise, each failure named on stderr.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build-hip}
archs=${MPMVS_HIP_ARCHITECTURES:-gfx90a}
fail() { echo "compile_hip: $*" >&2; exit 1; }

# shellcheck source=tests/gpu/install_missing.sh
. tests/gpu/install_missing.sh
command -v hipcc > /dev/null || install_missing hipcc || fail "could not install hipcc"
command -v hipcc > /dev/null || fail "no hipcc (Debian 12: apt-get install hipcc)"

config=$(cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMPMVS_ENABLE_HIP=ON \
  -DMPMVS_HIP_ARCHITECTURES="$archs" -DMPMVS_BUILD_TESTS=OFF -DMPMVS_BUILD_BENCHMARKS=OFF \
  -DMPMVS_WITH_COLMAP=OFF) || fail "configure of $build failed"
echo "$config" | grep "mp-mvs: HIP backend ON" || fail "configure did not turn the HIP backend on"

cmake --build "$build" -j "$(nproc)" --target colmap-mp || fail "build of $build failed"
# Whole outputs matched, not piped into grep -q (tests/early_exit_pipes_test.sh says why).
sections=$(objdump -h "$build/hip/cuda_backend.o") || fail "objdump cannot read $build/hip/cuda_backend.o"
[[ $sections == *hip_fatbin* ]] || fail "the kernels' object has no AMD device code"
libraries=$(ldd "$build/colmap-mp") || fail "ldd cannot read $build/colmap-mp"
[[ $libraries == *libamdhip64* ]] || fail "$build/colmap-mp does not link the HIP runtime"
echo "compile_hip: the kernels compiled for $archs into $build/colmap-mp"

scene=$(mktemp -d)
trap 'rm -rf "$scene"' EXIT
"$build/colmap-mp" generate_scene --scene plane --width 96 --height 72 --num_views 3 \
  --output_path "$scene/ws" > "$scene/generate.log" 2>&1 || fail "generate_scene failed (log: $(tail -3 "$scene/generate.log"))"
"$build/colmap-mp" mp_patch_match_stereo --workspace_path "$scene/ws" --MPMVS.preset fast \
  --MPMVS.write_pictures none > "$scene/run.log" 2>&1 || fail "the run failed: $(tail -3 "$scene/run.log")"
grep "No HIP device; running on the CPU" "$scene/run.log" || fail "the run did not say that it has no HIP device"
maps=$(ls "$scene/ws/stereo/depth_maps" | grep -c "geometric.bin$" || true)
[ "$maps" -eq 3 ] || fail "the run wrote $maps geometric depth maps, not 3"
echo "compile_hip: the HIP build ran on the CPU without an AMD GPU and wrote $maps depth maps"
