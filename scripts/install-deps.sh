#!/usr/bin/env bash
# Installs the Debian 12 packages Aeroform needs, only those that are missing.
# Runs as root, or through sudo when available.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  qt6-base-dev libqt6opengl6-dev qt6-charts-dev libvtk9-dev libeigen3-dev
  libocct-data-exchange-dev libocct-modeling-algorithms-dev
  libnlopt-cxx-dev coinor-libipopt-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev libsuitesparse-dev
  libopenblas0-openmp  # CHOLMOD (mesh movement fallback) is 4x slower on the reference BLAS
  xvfb xauth libgl1-mesa-dri
  libqt6svg6  # the desktop application's SVG icons (Qt's SVG icon engine, at run time only)
  clang-14 libomp-14-dev  # the ThreadSanitizer build (LLVM's OpenMP runtime and its Archer tool)
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "[deps] all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "[deps] missing packages: ${missing[*]}; run as root or install sudo" >&2; exit 1
  fi
fi
echo "[deps] installing: ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "[deps] done"
