#!/usr/bin/env bash
# Makes a CUDA build runnable on a bare GPU machine (the device tool copies the working tree and
# the carried build folder, but not this machine's /usr/lib packages): copies every shared
# library the GPU test, the benchmark and the CLI need, except glibc's and the CUDA driver's,
# into build/gpu_bundle. cudart and gtest are linked statically already.
# On the GPU machine: LD_LIBRARY_PATH=build/gpu_bundle build/tests/millsim_gpu_tests
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/gpu_bundle
rm -rf "$out" && mkdir -p "$out"
for bin in build/tests/millsim_gpu_tests build/tests/millsim_unit_tests build/bench/millsim_bench build/apps/millsim/millsim; do
  [ -x "$bin" ] || continue
  ldd "$bin" | awk '/=> \//{print $3}' |
    grep -vE '/(libc|libm|libdl|librt|libpthread|libresolv|ld-linux[^/]*|libcuda)\.so' |
    while read -r lib; do cp -Lu "$lib" "$out/"; done
done
ls "$out"
