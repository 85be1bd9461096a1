#!/usr/bin/env bash
# README command 2: set up, build (with tests), run the test suites with ctest, and build the
# find_package example against an installed copy. GPU tests skip with a message without a GPU.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh -DMILLSIM_BUILD_TESTS=ON -DMILLSIM_WERROR=ON
# Longest tests first: ctest orders by the costs of earlier runs, and a clean clone has none, so
# the ~10-minute towed-cylinder test would start late and be the critical path on 2 cores. Seed
# them from tests/ctest_costs.txt (measured CI run, tests over 10 s); ctest updates its copy.
mkdir -p build/Testing/Temporary
[ -f build/Testing/Temporary/CTestCostData.txt ] || cp tests/ctest_costs.txt build/Testing/Temporary/CTestCostData.txt
ctest --test-dir build --output-on-failure -j"$(nproc)" -LE slow
# The library as another project uses it: install to a prefix, build examples/ against it.
rm -rf build/install build/example
cmake --install build --prefix build/install >/dev/null
cmake -S examples/find_package -B build/example -DCMAKE_PREFIX_PATH="$PWD/build/install" >/dev/null
cmake --build build/example -j"$(nproc)" >/dev/null
./build/example/millsim_example
