#!/usr/bin/env bash
# Makes a CUDA build runnable on a bare GPU machine. The device tool copies the working tree and
# at most 64 MiB of carried build outputs, not this machine's /usr/lib packages, so this packs
# into ONE archive, build/gpu_pack.tar.xz (~25 MiB):
#   - the GPU test and the benchmark, stripped (cudart and gtest are linked statically; both
#     link with --as-needed, so they name only the libraries they call into),
#   - every shared library they need except glibc's and the CUDA driver's (~45 MiB unpacked:
#     HDF5, OpenCV core/imgproc for the plots, LAPACK; not OpenCV's codecs, which only the video
#     input uses), under build/gpu_bundle.
# The CLI and the other test binaries need OpenCV's video I/O (~270 MiB of libraries with
# FFmpeg), more than a run can carry, so they are not packed: GPU work goes through
# millsim_gpu_tests and millsim_bench.
# Carry build/gpu_pack.tar.xz; scripts/gpu_check.sh unpacks it (python3's tarfile: the device
# image may lack xz) and sets LD_LIBRARY_PATH.
set -euo pipefail
cd "$(dirname "$0")/.."
bins=(build/tests/millsim_gpu_tests build/bench/millsim_bench)
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/build/gpu_bundle" "$stage/build/tests" "$stage/build/bench"
for bin in "${bins[@]}"; do
  if [ ! -x "$bin" ]; then
    echo "gpu_bundle: $bin is missing (scripts/build.sh -DMILLSIM_BUILD_TESTS=ON with CUDA)" >&2
    exit 1
  fi
  strip -s -o "$stage/$bin" "$bin"
  ldd "$bin" | awk '/=> \//{print $3}' |
    grep -vE '/(libc|libm|libdl|librt|libpthread|libresolv|ld-linux[^/]*|libcuda)\.so' |
    while read -r lib; do cp -Lu "$lib" "$stage/build/gpu_bundle/"; done
done
du -sh "$stage/build/gpu_bundle" "$stage/build/tests" "$stage/build/bench"
tar -C "$stage" -cf - build | xz -6 -T0 >build/gpu_pack.tar.xz
size=$(stat -c %s build/gpu_pack.tar.xz)
echo "build/gpu_pack.tar.xz: $((size / 1048576)) MiB"
if [ "$size" -gt $((60 * 1048576)) ]; then
  echo "gpu_bundle: the pack is over 60 MiB; the device tool carries at most 64 MiB" >&2
  exit 1
fi
