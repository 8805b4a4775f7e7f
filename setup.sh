#!/usr/bin/env bash
# Installs mp-mvs's dependencies from Debian packages (only what is missing) and builds
# the project into build/. Safe to run again: with everything in place it only rebuilds
# what changed.
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libboost-program-options-dev libcgal-dev libgmp-dev libmpfr-dev
  libfreeimage-dev libnanoflann-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  colmap
  slurm-wlm munge
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if [[ $(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null) != *"install ok installed"* ]]; then
    missing+=("$pkg")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup.sh: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# CUDA: used when nvcc exists (default /usr/local/cuda); the CPU backend always works.
export PATH="$PATH:/usr/local/cuda/bin"
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j "$(nproc)"
echo "setup.sh: built build/colmap-mp"
# Say plainly whether the CUDA backend is in the binary (it is compiled and linked here
# even without a GPU; it only runs where a CUDA device exists).
if [ "$(nm -C build/colmap-mp 2> /dev/null | grep -c CheckerboardKernel || true)" -gt 0 ]; then
  archs=$(strings build/colmap-mp | grep -o "sm_[0-9][0-9]" | sort -u | grep -v sm_30 | tr "\n" " " || true)
  echo "setup.sh: CUDA backend compiled and linked into build/colmap-mp (device code for: ${archs})"
else
  echo "setup.sh: build/colmap-mp has no CUDA backend (CPU only)"
fi
