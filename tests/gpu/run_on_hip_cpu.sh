#!/usr/bin/env bash
# tests/gpu/run_on_hip_cpu.sh HIP_CPU_DIR
#
# The GPU backend's own code (kernels/*.cu: kernels, launch geometry, session, uploads,
# downloads) run on the CPU through HIP-CPU, a header-only runtime that executes HIP programs
# on the CPU, and compared with the CPU backend. HIP_CPU_DIR is the root of an extracted
# HIP-CPU source tree (github.com/ROCm/HIP-CPU; never part of this repository). Not part of
# CI: it needs that tree. Steps:
#   1. Configure and build build-hip-cpu (-DMPMVS_HIP_CPU_DIR, cmake/hip_cpu_backend.cmake):
#      colmap-mp and mpmvs_tests, whose GPU backend is the HIP code on HIP-CPU; and
#      build-hip-cpu-reference, the CPU backend alone. Both without -march=native
#      (MPMVS_NATIVE_ARCH=OFF), so that both compile the shared per-pixel code to the same
#      instructions: no fused multiply-adds in one and not the other, the scalar NCC in both.
#      Installs Debian's libtbb-dev when missing. build/colmap-mp (./setup.sh, -march=native:
#      the CPU backend users run) is compared too.
#   2. The GPU tests (ctest Cuda*.*) on HIP-CPU: all must pass but
#      CudaDevice.RunWithoutDeviceThrows, which skips where a device exists.
#   3. Scenes: middlebury2005_dolls (../shared/data, a workspace from colmap image_undistorter)
#      and the synthetic 5-view indoor scene (colmap-mp generate_scene).
#   4. Per scene, the GPU code, the reference CPU backend and build/'s: one photometric
#      iteration (11 px window, no geometric stages, no prior), compared with the GPU code's
#      over the pixels with a depth in either map (share within 1e-4 relative depth, largest
#      difference); then the whole default pipeline, each scored against ground truth (depth
#      F1 at 1 %, geometric maps), and the GPU code's geometric maps against the reference's.
# Prints the tables (also into a file beside the logs in build-hip-cpu/hip_cpu_check) and, as its last line,
# exactly: agreement NN.NN %, F1 cpu NN.NN, F1 gpu-code NN.NN (GPU code against the reference
# CPU backend: the agreement after one iteration, the minimum over the scenes; the F1 of the
# scene where the GPU code's falls furthest below the CPU's). Exit 0 when every step ran, 1
# otherwise; 2 on a usage error.
set -uo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
if [ $# -ne 1 ] || [ ! -f "$1/include/hip/hip_runtime.h" ]; then
  echo "usage: tests/gpu/run_on_hip_cpu.sh HIP_CPU_DIR  (the root of a HIP-CPU source tree)" >&2
  exit 2
fi
HIP_CPU_DIR=$(cd "$1" && pwd)
BUILD=${MPMVS_HIP_CPU_BUILD_DIR:-$REPO/build-hip-cpu}
OUT=$BUILD/hip_cpu_check
DATA=${MPMVS_SHARED_DATA_DIR:-$REPO/../shared/data}
NATIVE_EXE=$REPO/build/colmap-mp
START=$SECONDS
log() { printf '[%4ds] %s\n' $((SECONDS - START)) "$*"; }
die() { log "FAILED: $*"; exit 1; }
[ -x "$NATIVE_EXE" ] || { echo "run_on_hip_cpu.sh: no $NATIVE_EXE (run ./setup.sh first)" >&2; exit 2; }

# HIP-CPU runs a kernel's blocks with the C++17 parallel algorithms (TBB).
# shellcheck source=tests/gpu/install_missing.sh
. "$REPO/tests/gpu/install_missing.sh"
install_missing libtbb-dev || die "could not install libtbb-dev"
mkdir -p "$BUILD"
rm -rf "$OUT"
mkdir -p "$OUT"

# ---- 1. Builds
log "configuring and building $BUILD (against $HIP_CPU_DIR) and $BUILD-reference: $OUT/build.log"
generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
common=(-DCMAKE_BUILD_TYPE=Release -DMPMVS_NATIVE_ARCH=OFF -DMPMVS_WITH_COLMAP=OFF -DMPMVS_BUILD_BENCHMARKS=OFF)
cmake -S "$REPO" -B "$BUILD" "${generator[@]}" "${common[@]}" -DMPMVS_HIP_CPU_DIR="$HIP_CPU_DIR" \
  > "$OUT/build.log" 2>&1 || die "configure failed (build.log)"
grep -q "mp-mvs: HIP-CPU backend ON" "$OUT/build.log" || die "configure did not turn the HIP-CPU backend on"
cmake --build "$BUILD" -j "$(nproc)" --target colmap-mp mpmvs_tests >> "$OUT/build.log" 2>&1 || die "build failed (build.log)"
cmake -S "$REPO" -B "$BUILD-reference" "${generator[@]}" "${common[@]}" -DMPMVS_ENABLE_CUDA=OFF \
  -DMPMVS_BUILD_TESTS=OFF >> "$OUT/build.log" 2>&1 || die "configure of the reference failed (build.log)"
cmake --build "$BUILD-reference" -j "$(nproc)" --target colmap-mp >> "$OUT/build.log" 2>&1 ||
  die "build of the reference failed (build.log)"
GPU_EXE=$BUILD/colmap-mp
CPU_EXE=$BUILD-reference/colmap-mp

# ---- 2. GPU tests
log "GPU tests on HIP-CPU: $OUT/gpu_tests.log"
ctest --test-dir "$BUILD" -R '^Cuda[A-Za-z]*\.' --output-on-failure --timeout 600 > "$OUT/gpu_tests.log" 2>&1 ||
  die "GPU tests failed (gpu_tests.log)"
skipped=$(sed -n 's/.* - \(Cuda[A-Za-z]*\.[A-Za-z]*\) (Skipped).*/\1/p' "$OUT/gpu_tests.log" |
  grep -vx 'CudaDevice.RunWithoutDeviceThrows' || true)
[ -z "$skipped" ] || die "GPU tests skipped on HIP-CPU: $skipped"
log "$(grep -m 1 'tests passed' "$OUT/gpu_tests.log")"

# ---- 3. Scenes
mkdir -p "$OUT/dolls" "$OUT/indoor5"
if [ -d "$DATA/middlebury2005_dolls/images" ]; then
  colmap image_undistorter --image_path "$DATA/middlebury2005_dolls/images" \
    --input_path "$DATA/middlebury2005_dolls/sparse" --output_path "$OUT/dolls/base" \
    --output_type COLMAP > "$OUT/dolls/prepare.log" 2>&1 || die "image_undistorter on dolls failed"
  ln -s "$DATA/middlebury2005_dolls/gt" "$OUT/dolls/gt"
  SCENES=(dolls indoor5)
else
  log "no $DATA/middlebury2005_dolls: the synthetic scene alone"
  SCENES=(indoor5)
fi
"$CPU_EXE" generate_scene --scene indoor --num_views 5 --output_path "$OUT/indoor5/base" \
  > "$OUT/indoor5/prepare.log" 2>&1 || die "generate_scene failed"
mv "$OUT/indoor5/base/gt" "$OUT/indoor5/gt"

# ---- 4. Runs
ONE_ITERATION=(--MPMVS.max_window_scale 0 --MPMVS.iterations_per_scale 1
  --PatchMatchStereo.geom_consistency 0 --MPMVS.planar_prior none)
# run SIDE DIR NAME [options]: SIDE's colmap-mp (gpu, cpu or native) on a copy of DIR/base in
# DIR/ws_NAME, at most 10 minutes; the log must name the backend SIDE stands for.
run() {
  local side=$1 dir=$2 name=$3 exe=$CPU_EXE backend="CPU ("
  shift 3
  [ "$side" = gpu ] && exe=$GPU_EXE backend="HIP-CPU device 0"
  [ "$side" = native ] && exe=$NATIVE_EXE
  rm -rf "$dir/ws_$name"
  cp -r "$dir/base" "$dir/ws_$name"
  timeout 600 "$exe" mp_patch_match_stereo --workspace_path "$dir/ws_$name" --MPMVS.write_pictures none \
    --PatchMatchStereo.num_threads "$(nproc)" "$@" > "$dir/log_$name.txt" 2>&1 || return 1
  grep -q "backend $backend" "$dir/log_$name.txt"
}
agreement() {  # agreement DIR A B KIND: DIR/ws_B against DIR/ws_A into DIR/agreement_A_B.json
  python3 "$REPO/tests/gpu/device_report.py" agreement "$1/ws_$2" "$1/ws_$3" "$4" > "$1/agreement_$2_$3.json"
}
for scene in "${SCENES[@]}"; do
  dir=$OUT/$scene
  log "$scene"
  for side in gpu cpu native; do
    run $side "$dir" ${side}_1it "${ONE_ITERATION[@]}" || die "$scene: one iteration ($side, log_${side}_1it.txt)"
    run $side "$dir" $side || die "$scene: the default pipeline ($side, log_$side.txt)"
    "$NATIVE_EXE" evaluate --workspace_path "$dir/ws_$side" --gt_path "$dir/gt" --fused_path none --pictures 0 \
      --output_path "$dir/eval_$side" > "$dir/eval_$side.log" 2>&1 || die "$scene: evaluate ($side)"
  done
  { agreement "$dir" cpu_1it gpu_1it photometric && agreement "$dir" native_1it gpu_1it photometric &&
    agreement "$dir" cpu gpu geometric; } || die "$scene: agreement"
done

python3 - "$REPO/tests/gpu" "$OUT" "${SCENES[@]}" << 'PYTHON'
import json, os, sys
sys.path.insert(0, sys.argv[1])
from device_report import f1_at_1_percent
out, scenes = sys.argv[2], sys.argv[3:]

def f1(scene, side):
    path = os.path.join(out, scene, f"eval_{side}", "evaluation.json")
    value = f1_at_1_percent(path)
    if value is None:
        raise ValueError(f"no F1 at 1 % in {path}")
    return 100 * value

def agreement(scene, a, b):
    return json.load(open(os.path.join(out, scene, f"agreement_{a}_{b}.json")))

lines = ["GPU code (HIP-CPU) against a CPU backend, over the pixels with a depth in either map:", "",
         "| scene | against | maps | pixels | within 1e-4 | within 1e-2 | depth in one only | largest rel. diff |",
         "|---|---|---|---|---|---|---|---|"]
for s in scenes:
    for label, a, b in (("reference, 1 iteration", "cpu_1it", "gpu_1it"),
                        ("reference, whole run", "cpu", "gpu"),
                        ("build/ (-march=native), 1 iteration", "native_1it", "gpu_1it")):
        r = agreement(s, a, b)
        lines.append(f"| {s} | {label} | {r['maps']} | {r['pixels']} | {100 * r['within_1e-4']:.3f} % | "
                     f"{100 * r['within_1e-2']:.3f} % | {100 * r['depth_in_one_only']:.3f} % | "
                     f"{r['largest_rel_diff']:.2e} |")
lines += ["", "Depth F1@1 % of the whole default pipeline:", "",
          "| scene | GPU code | reference CPU backend | build/ CPU backend |", "|---|---|---|---|"]
worst = None
for s in scenes:
    gpu, cpu, native = f1(s, "gpu"), f1(s, "cpu"), f1(s, "native")
    lines.append(f"| {s} | {gpu:.2f} | {cpu:.2f} | {native:.2f} |")
    if worst is None or gpu - cpu < worst[1] - worst[0]:
        worst = (cpu, gpu)
open(os.path.join(out, "tables.txt"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
low = min(100 * agreement(s, "cpu_1it", "gpu_1it")["within_1e-4"] for s in scenes)
print(f"agreement {low:.2f} %, F1 cpu {worst[0]:.2f}, F1 gpu-code {worst[1]:.2f}")
PYTHON
