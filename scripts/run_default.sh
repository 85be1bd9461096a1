#!/usr/bin/env bash
# README command 1: set up, build, and run the embedded default case (300 mm balls-only mill of
# the paper) into ./out. Arguments are passed to `millsim run`, e.g. --set time.end=4.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh -DMILLSIM_BUILD_TESTS=OFF -DMILLSIM_BUILD_BENCH=OFF
./build/apps/millsim/millsim run --out out "$@"
