#!/usr/bin/env bash
# Installs millsim's build dependencies from Debian 12 packages. Idempotent: skips apt entirely
# when every package is already installed. nvcc (CUDA) is optional: with it, the CUDA backend is
# built as well (MILLSIM_CUDA=AUTO). libopencv-dev brings OpenCV's videoio with Debian's FFmpeg
# backend (mp4/avi decoding and encoding for src/vision). Open MPI: `mpirun -np N millsim calibrate|sweep`
# (docs/cluster.md).
set -euo pipefail
packages=(build-essential cmake libhdf5-dev hdf5-tools libtinyxml2-dev nlohmann-json3-dev libcli11-dev
          libpng-dev libgtest-dev libbenchmark-dev libeigen3-dev libopencv-dev libopenmpi-dev openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
