#!/usr/bin/env bash
# tests/gpu/check_on_device.sh OUT  (or --probe)
#
# The CUDA backend on a real NVIDIA GPU in one command, for a machine with one current NVIDIA
# GPU, many cores, nvcc and mp-mvs's dependencies (setup.sh). Budget: 6 minutes, build
# included. Nothing in this project has run on a GPU yet (README.md, "What has run where");
# this is the check to run the first time one is at hand. Steps:
#   1. Device. `nvidia-smi -L` must list a GPU, and a tiny CUDA program (device_probe.cu, built
#      with the nvcc that builds mp-mvs) must see device 0 and run a kernel on it. Without one:
#      exactly one line "no GPU: <why>" and exit 77, before anything is configured, built or
#      written. `--probe` stops after this step (one line "GPU: ..." and exit 0, or as above).
#   2. Configure $MPMVS_GPU_BUILD_DIR (default build-gpu) with the CUDA backend for the device's
#      compute capability alone (the probe's), without the native COLMAP command or benchmarks.
#   3. Build colmap-mp and mpmvs_tests with all cores.
#   4. GPU tests: the ctest tests Cuda*.* (CudaBackend, CudaSession, CudaDevice,
#      CudaLaunchLayout). One that skips fails the check (a device is there), except
#      CudaDevice.RunWithoutDeviceThrows, which skips where a device exists.
#   5. Scenes: each ../shared/data scene with gt/ (a workspace from `colmap image_undistorter`,
#      docs/evaluation.md §1) and a synthetic room_window (`colmap-mp generate_scene`).
#   6. Per scene, on the GPU (--PatchMatchStereo.gpu_index 0) and on the CPU (the environment
#      CUDA_VISIBLE_DEVICES= hides the GPU: no option forces the CPU backend where a device
#      exists): one photometric iteration, then the whole default pipeline; each run's log must
#      name the backend it was meant for. `colmap-mp evaluate` scores both whole runs;
#      nvidia-smi samples device memory every 100 ms during the GPU's whole run.
#   7. The report $REPORT in OUT, written by this script (device_report.py; its layout:
#      kernels/DESIGN_CUDA.md, "Checking on a device", step 7): agreement of the maps (share of the pixels with a depth
#      in either map whose relative depth difference is <= 1e-4), F1@1 % of each, time per map,
#      cost samples/s, peak device memory; the logs beside it (build.log, gpu_tests.log,
#      runs.log). Exit 0 when every step ran, 1 when one failed, 2 on a usage or setup error.
#
# Budget (6 minutes; estimates from runs on 2 shared cores here, none measured on a GPU
# machine): building the whole project took about 5 minutes on 2 cores, so perhaps one on 16;
# the CUDA files for one architecture take seconds. A whole default run of a Middlebury pair
# (0.17-0.36 Mpx per view) takes 12-27 CPU-seconds, about 1-3 s on 16 cores; a 10-view 640x480
# room takes 340 CPU-seconds, too much for the CPU's share, so the room is rendered at 320x240
# with 8 views (about 50 CPU-seconds, still 7 sources per view for the device's view selection
# and cache). Pictures are off in every run (host work). The scenes run in the order of
# SCENES below; once 300 s have passed the scenes not yet begun are left out, and the report
# says so.
#
# Environment: MPMVS_GPU_BUILD_DIR (build folder), MPMVS_SHARED_DATA_DIR (default
# ../shared/data beside the repository), MPMVS_CHECK_SCENES (space-separated scene names
# instead of the default list), NVCC (else CUDACXX, nvcc on PATH, /usr/local/cuda/bin/nvcc).
set -uo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
HERE=$REPO/tests/gpu
PROBE_ONLY=0
if [ "${1:-}" = "--probe" ] && [ $# -eq 1 ]; then
  PROBE_ONLY=1
elif [ $# -ne 1 ] || [ -z "$1" ] || [ "${1#-}" != "$1" ]; then
  echo "usage: tests/gpu/check_on_device.sh OUT   (or --probe: only say whether a GPU is there)" >&2
  exit 2
fi

# ---- 1. Device --------------------------------------------------------------------------
no_gpu() {
  echo "no GPU: $*"
  exit 77
}
# The first non-empty line of $1, or "no output"; no pipe into grep -m under pipefail.
first_line() {
  local line
  while IFS= read -r line; do
    [ -n "$line" ] && { printf '%s' "$line"; return; }
  done <<< "$1"
  printf 'no output'
}

SMI=$(command -v nvidia-smi || true)
[ -z "$SMI" ] && [ -x /usr/local/nvidia/bin/nvidia-smi ] && SMI=/usr/local/nvidia/bin/nvidia-smi
if [ -n "$SMI" ]; then
  smi_list=$(timeout 60 "$SMI" -L 2>&1)
  smi_rc=$?
  if [ $smi_rc -ne 0 ]; then
    no_gpu "nvidia-smi -L failed (exit $smi_rc): $(first_line "$smi_list")"
  fi
  smi_gpu=$(grep '^GPU [0-9]' <<< "$smi_list" | sed -n 1p || true)
  [ -n "$smi_gpu" ] || no_gpu "nvidia-smi -L lists no GPU ($(first_line "$smi_list"))"
elif ! ls /dev/nvidia[0-9]* > /dev/null 2>&1 && [ ! -e /proc/driver/nvidia ]; then
  no_gpu "no NVIDIA driver (no nvidia-smi, no /dev/nvidia0, no /proc/driver/nvidia)"
else
  smi_gpu="an NVIDIA driver, no nvidia-smi"  # the runtime probe decides
fi

NVCC=${NVCC:-${CUDACXX:-$(command -v nvcc || true)}}
[ -z "$NVCC" ] && [ -x /usr/local/cuda/bin/nvcc ] && NVCC=/usr/local/cuda/bin/nvcc
if [ -z "$NVCC" ]; then
  if [ $PROBE_ONLY -eq 1 ]; then
    echo "GPU: $smi_gpu (no nvcc: the CUDA runtime probe did not run)"
    exit 0
  fi
  echo "check_on_device.sh: $smi_gpu is there, but no nvcc was found (set NVCC)" >&2
  exit 2
fi
probe_dir=$(mktemp -d)
trap 'rm -rf "$probe_dir"' EXIT
if ! "$NVCC" -o "$probe_dir/device_probe" "$HERE/device_probe.cu" > "$probe_dir/nvcc.log" 2>&1; then
  echo "check_on_device.sh: $NVCC could not build the device probe:" >&2
  cat "$probe_dir/nvcc.log" >&2
  exit 2
fi
probe=$(timeout 60 "$probe_dir/device_probe" 2>&1)
probe_rc=$?
if [ $probe_rc -ne 0 ]; then
  no_gpu "the CUDA runtime of $NVCC cannot use device 0 ($smi_gpu): $(first_line "$probe" | sed 's/^error=//') (probe exit $probe_rc)"
fi
probe_value() { sed -n "s/^$1=//p" <<< "$probe" | sed -n 1p; }
GPU_NAME=$(probe_value name)
GPU_CC=$(probe_value cc)
GPU_UUID=$(probe_value uuid)
if [ $PROBE_ONLY -eq 1 ]; then
  echo "GPU: $GPU_NAME, compute capability $GPU_CC (CUDA device 0; $smi_gpu)"
  exit 0
fi

# ---- a device is there: the check proper ------------------------------------------------
START=$SECONDS
OUT=$1
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)
BUILD=${MPMVS_GPU_BUILD_DIR:-$REPO/build-gpu}
DATA=${MPMVS_SHARED_DATA_DIR:-$REPO/../shared/data}
WORK=$BUILD/check_on_device   # workspaces and per-scene results (large; OUT keeps the report and logs)
CORES=$(nproc)
SCENE_CUTOFF_S=300
FAILED=0 CHECK_NOTES="" STEP_TIMES="" GPU_TESTS=""
command -v python3 > /dev/null || { echo "check_on_device.sh: needs python3 (device_report.py)" >&2; exit 2; }
command -v cmake > /dev/null || { echo "check_on_device.sh: needs cmake (setup.sh)" >&2; exit 2; }
REPORT=$OUT/device_report.txt  # Markdown text: the list and tables of kernels/DESIGN_CUDA.md step 7
rm -f "$REPORT" "$OUT"/build.log "$OUT"/gpu_tests.log "$OUT"/runs.log
log() { printf '[%4ds] %s\n' $((SECONDS - START)) "$*"; }

# Writes $REPORT (the header lines below, then device_report.py's tables) from what is there
# so far, prints it and exits with the check's status.
finish() {
  local status=$1
  {
    echo "# mp-mvs on a GPU: tests/gpu/check_on_device.sh"
    echo
    echo "- When: $(date -u '+%Y-%m-%d %H:%M UTC'); commit $(commit_text)"
    echo "- Device: $GPU_NAME, compute capability $GPU_CC, $(probe_value memory_mib) MiB," \
      "$(probe_value multiprocessors) multiprocessors; driver CUDA $(probe_value driver), runtime $(probe_value runtime); $smi_gpu"
    echo "- Host: $CORES cores; nvcc $("$NVCC" --version | sed -n 's/.*release \([0-9.]*\).*/\1/p')"
    echo "- Steps: ${STEP_TIMES:-none}; $((SECONDS - START)) s in all"
    echo "- GPU tests: ${GPU_TESTS:-not run}"
    printf '%s' "$CHECK_NOTES"
    echo "- Result: $([ "$status" -eq 0 ] && echo 'every step ran' || echo 'FAILED: see the notes and the logs beside this report')"
  } > "$WORK/header.txt"
  if [ -f "$WORK/scenes.txt" ]; then
    python3 "$HERE/device_report.py" report "$WORK" "$REPORT" || { status=1; cp "$WORK/header.txt" "$REPORT"; }
  else
    cp "$WORK/header.txt" "$REPORT"
  fi
  if ls "$WORK"/*/log_*.txt > /dev/null 2>&1; then
    for f in "$WORK"/*/log_*.txt; do
      echo "===== ${f#"$WORK"/}"
      cat "$f"
    done > "$OUT/runs.log"
  fi
  cat "$REPORT"
  exit "$status"
}
commit_text() {
  local commit
  commit=$(git -C "$REPO" rev-parse --short HEAD 2> /dev/null) || { echo unknown; return; }
  if git -C "$REPO" diff --quiet HEAD 2> /dev/null; then echo "$commit"; else echo "$commit with local changes"; fi
}
note() {  # a line for the report's header; marks the check failed when the first argument is "fail"
  if [ "$1" = fail ]; then FAILED=1; shift; fi
  CHECK_NOTES+="- Note: $*"$'\n'
  log "$*"
}
step_done() { STEP_TIMES+="${STEP_TIMES:+, }$1 $((SECONDS - step_start)) s"; }

rm -rf "$WORK"
mkdir -p "$WORK" || exit 2
log "GPU: $GPU_NAME, compute capability $GPU_CC; OUT=$OUT, build folder $BUILD"

# ---- 2-3. Configure and build -------------------------------------------------------------
step_start=$SECONDS
generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
log "configuring and building (architecture $GPU_CC, $CORES cores): $OUT/build.log"
if ! cmake -S "$REPO" -B "$BUILD" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DMPMVS_ENABLE_CUDA=ON \
  -DCMAKE_CUDA_COMPILER="$NVCC" -DMPMVS_CUDA_ARCHITECTURES="$GPU_CC" -DMPMVS_WITH_COLMAP=OFF \
  -DMPMVS_BUILD_BENCHMARKS=OFF > "$OUT/build.log" 2>&1; then
  note fail "configure failed (build.log)"
  finish 1
fi
if ! grep -q "mp-mvs: CUDA backend ON" "$OUT/build.log"; then
  note fail "configure did not turn the CUDA backend on (build.log)"
  finish 1
fi
if ! cmake --build "$BUILD" --parallel "$CORES" --target colmap-mp mpmvs_tests >> "$OUT/build.log" 2>&1; then
  note fail "build failed (build.log)"
  finish 1
fi
step_done "configure and build"
COLMAP_MP=$BUILD/colmap-mp

# ---- 4. GPU tests -------------------------------------------------------------------------
step_start=$SECONDS
log "GPU tests: $OUT/gpu_tests.log"
ctest --test-dir "$BUILD" -R '^Cuda[A-Za-z]*\.' --output-on-failure --timeout 300 > "$OUT/gpu_tests.log" 2>&1
ctest_rc=$?
GPU_TESTS=$(grep -m 1 'tests passed' "$OUT/gpu_tests.log" || echo "no summary (exit $ctest_rc)")
skipped=$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/\1/p' "$OUT/gpu_tests.log" |
  grep -vx 'CudaDevice.RunWithoutDeviceThrows' | tr '\n' ' ')
[ -n "$skipped" ] && GPU_TESTS+="; skipped although a device is there: $skipped"
if [ $ctest_rc -ne 0 ] || [ -n "$skipped" ] || ! grep -q 'tests passed' "$OUT/gpu_tests.log"; then
  note fail "GPU tests failed or skipped (gpu_tests.log)"
fi
step_done "GPU tests"

# ---- 5. Scenes ----------------------------------------------------------------------------
# The three Middlebury pairs named in issue 34 and the room first, then every other scene of
# DATA that has ground truth.
if [ -n "${MPMVS_CHECK_SCENES:-}" ]; then
  read -r -a SCENES <<< "$MPMVS_CHECK_SCENES"
else
  SCENES=(middlebury2005_dolls middlebury2005_reindeer middlebury2014_adirondack room_window)
  for d in "$DATA"/*/; do
    name=$(basename "$d")
    [ -d "$d/gt" ] && [[ " ${SCENES[*]} " != *" $name "* ]] && SCENES+=("$name")
  done
fi
HAVE_COLMAP=0
command -v colmap > /dev/null && HAVE_COLMAP=1
[ $HAVE_COLMAP -eq 1 ] || note "no colmap executable: no Middlebury workspaces, the room's sparse points simulated"
[ -d "$DATA" ] || note "no data folder $DATA (MPMVS_SHARED_DATA_DIR): the room alone"

# prepare SCENE DIR: a dense workspace in DIR/base with its ground truth in DIR/gt.
prepare() {
  local scene=$1 dir=$2
  if [ "$scene" = room_window ]; then
    local sparse=sift
    [ $HAVE_COLMAP -eq 1 ] || sparse=simulated
    "$COLMAP_MP" generate_scene --scene room_window --width 320 --height 240 --num_views 8 \
      --sparse_source "$sparse" --output_path "$dir/base" > "$dir/prepare.log" 2>&1 &&
      mv "$dir/base/gt" "$dir/gt"
  else
    local src=$DATA/$scene
    if [ ! -d "$src/images" ] || [ ! -d "$src/sparse" ] || [ ! -d "$src/gt" ]; then
      echo "no $src/{images,sparse,gt}" > "$dir/prepare.log"
      return 1
    fi
    [ $HAVE_COLMAP -eq 1 ] || { echo "needs colmap (image_undistorter)" > "$dir/prepare.log"; return 1; }
    colmap image_undistorter --image_path "$src/images" --input_path "$src/sparse" \
      --output_path "$dir/base" --output_type COLMAP > "$dir/prepare.log" 2>&1 &&
      ln -s "$src/gt" "$dir/gt"
  fi
}

# ---- 6. Runs ------------------------------------------------------------------------------
ONE_ITERATION=(--MPMVS.max_window_scale 0 --MPMVS.iterations_per_scale 1
  --PatchMatchStereo.geom_consistency 0 --MPMVS.planar_prior none)

# run BACKEND DIR NAME [options]: mp_patch_match_stereo on a copy of DIR/base in DIR/ws_NAME,
# logged to DIR/log_NAME.txt; fails unless the log names BACKEND's backend.
run() {
  local backend=$1 dir=$2 name=$3
  shift 3
  rm -rf "$dir/ws_$name"
  cp -r "$dir/base" "$dir/ws_$name" || return 1
  local args=(mp_patch_match_stereo --workspace_path "$dir/ws_$name" --MPMVS.write_pictures none "$@")
  if [ "$backend" = gpu ]; then
    "$COLMAP_MP" "${args[@]}" --PatchMatchStereo.gpu_index 0 > "$dir/log_$name.txt" 2>&1 || return 1
    grep -q "backend CUDA device 0$" "$dir/log_$name.txt"
  else
    CUDA_VISIBLE_DEVICES="" "$COLMAP_MP" "${args[@]}" --PatchMatchStereo.gpu_index -1 > "$dir/log_$name.txt" 2>&1 ||
      return 1
    grep -q "backend CPU (" "$dir/log_$name.txt"
  fi
}

# sample_memory FILE: the probed device's memory.used (MiB, nvidia-smi) about every 100 ms
# into FILE, in the background until killed (one nvidia-smi per sample: each line is on disk
# at once, whatever signal ends the loop).
sample_memory() {
  while :; do
    "$SMI" --query-gpu=memory.used --format=csv,noheader,nounits ${GPU_UUID:+-i "$GPU_UUID"}
    sleep 0.1
  done > "$1" 2>&1 &
  SAMPLER=$!
}

# check_scene SCENE DIR: steps 5 and 6 for one scene; problems go to DIR/notes.txt.
check_scene() {
  local scene=$1 dir=$2 backend
  if [ $((SECONDS - START)) -ge $SCENE_CUTOFF_S ]; then
    echo "left out: ${SCENE_CUTOFF_S} s of the 6-minute budget had passed" >> "$dir/notes.txt"
    return
  fi
  if ! prepare "$scene" "$dir"; then
    echo "could not prepare the workspace: $(tail -n 1 "$dir/prepare.log")" >> "$dir/notes.txt"
    return
  fi
  for backend in gpu cpu; do
    run "$backend" "$dir" "${backend}_1it" "${ONE_ITERATION[@]}" ||
      { echo "the one-iteration run on the $backend failed or ran elsewhere (runs.log)" >> "$dir/notes.txt"; FAILED=1; }
    if [ "$backend" = gpu ] && [ -n "$SMI" ]; then
      "$SMI" --query-gpu=memory.used --format=csv,noheader,nounits ${GPU_UUID:+-i "$GPU_UUID"} \
        > "$dir/gpu_memory_before.txt" 2>&1
      sample_memory "$dir/gpu_memory.txt"
    fi
    run "$backend" "$dir" "$backend" ||
      { echo "the whole run on the $backend failed or ran elsewhere (runs.log)" >> "$dir/notes.txt"; FAILED=1; }
    if [ "$backend" = gpu ] && [ -n "$SMI" ]; then
      kill "$SAMPLER" 2> /dev/null
      wait "$SAMPLER" 2> /dev/null
    fi
    "$COLMAP_MP" evaluate --workspace_path "$dir/ws_$backend" --gt_path "$dir/gt" --fused_path none --pictures 0 \
      --output_path "$dir/eval_$backend" > "$dir/eval_$backend.log" 2>&1 ||
      echo "colmap-mp evaluate of the $backend run failed (eval_$backend.log)" >> "$dir/notes.txt"
  done
}

step_start=$SECONDS
printf '%s\n' "${SCENES[@]}" > "$WORK/scenes.txt"
for scene in "${SCENES[@]}"; do
  log "$scene"
  mkdir -p "$WORK/$scene"
  check_scene "$scene" "$WORK/$scene"
  python3 "$HERE/device_report.py" scene "$WORK/$scene" ||
    { echo "device_report.py scene failed" >> "$WORK/$scene/notes.txt"; FAILED=1; }
done
step_done "scenes"

# ---- 7. Report ----------------------------------------------------------------------------
log "report: $REPORT"
finish $FAILED
