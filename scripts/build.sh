#!/usr/bin/env bash
# Configures and builds millsim in ./build (Release). Extra arguments go to cmake, e.g.
# scripts/build.sh -DMILLSIM_CUDA=OFF. CUDA is built when nvcc is found (AUTO).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"
