#!/usr/bin/env bash
# Makes a CUDA build runnable on a bare GPU machine (the device tool copies the working tree and
# the carried build folder, but not this machine's /usr/lib packages): copies every shared
# library the GPU test and the benchmark need, except glibc's and the CUDA driver's, into
# build/gpu_bundle (about 3 MiB; cudart and gtest are linked statically already). The CLI and
# the other test binaries need OpenCV (video I/O and plots: ~270 MiB of libraries with FFmpeg),
# more than a run can carry (64 MiB), so they are not bundled: GPU work goes through
# millsim_gpu_tests and millsim_bench, which link only the engines.
# On the GPU machine: LD_LIBRARY_PATH=build/gpu_bundle build/tests/millsim_gpu_tests
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/gpu_bundle
rm -rf "$out" && mkdir -p "$out"
for bin in build/tests/millsim_gpu_tests build/bench/millsim_bench; do
  [ -x "$bin" ] || continue
  ldd "$bin" | awk '/=> \//{print $3}' |
    grep -vE '/(libc|libm|libdl|librt|libpthread|libresolv|ld-linux[^/]*|libcuda)\.so' |
    while read -r lib; do cp -Lu "$lib" "$out/"; done
done
ls "$out"
du -sh "$out"
