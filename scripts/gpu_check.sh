#!/usr/bin/env bash
# Every GPU check in one pass, for a lent GPU machine (issue 10; device time is short, so this is
# prepared and tried here first, where the GPU parts skip):
#   1. millsim_gpu_tests: CUDA against OpenMP (DEM drum, stirred slice, ensemble, SPH dam break
#      front, SPH-DEM momentum budget, the wet mill's pour and coupled steps, and every case in
#      cases/ over a short stretch),
#   2. millsim_bench: DEM and SPH throughput at N = 1e4 .. 1e6 on both backends and 1e7 on the
#      GPU (BM_DemScaling, BM_SphScaling3d; SPH in double and float), JSON per run;
#   3. millsim_bench: an ensemble of 18 drums against one drum on the GPU (BM_DrumEnsemble);
#   4. millsim_bench: the coupled wet mill (SPH-DEM) at N = 1e4 .. 1e6 on both backends and 1e7
#      on the GPU (BM_CoupledScaling);
#   5. millsim_bench: the full LS1 stirred mill (128 000 beads), 1 ms on both backends, then the
#      seed's 52.5 ms on the GPU (BM_StirredLs1); on request (ls1_program) its whole speed program
#      with outputs, OUT/ls1_program.tar.gz; on request (case) any case file whole with outputs.
# Each stage has its own time limit, so one that hangs costs only its share. GPU_STAGES picks the
# stages (default all: "tests ls1 dem sph ensemble coupled"), so the checks can be split over two
# calls of the device tool (each at most 600 s), the second while the machine is still warm.
#
# Here: scripts/build.sh -DMILLSIM_BUILD_TESTS=ON (CUDA on), bash scripts/gpu_bundle.sh, then run
# on the device machine with carry = build/gpu_pack.tar.xz (the two binaries, stripped, and their
# libraries; unpacked below):
#   bash scripts/gpu_check.sh "$OUT"
# Results: OUT/gpu_tests.{txt,json}, OUT/bench_*.json, OUT/summary.txt (one line per benchmark:
# name, particles, particle-steps/s).
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-${OUT:-/tmp/gpu_check}}
mkdir -p "$out"
# Always from the pack when one is carried: a warm machine keeps the last call's unpacked files.
if [ -f build/gpu_pack.tar.xz ]; then
  rm -rf build/tests build/bench build/gpu_bundle
  python3 -c 'import tarfile; tarfile.open("build/gpu_pack.tar.xz").extractall(".")' ||
    { echo "gpu_check: cannot unpack build/gpu_pack.tar.xz (python3 with lzma needed)" >&2; exit 1; }
fi
export LD_LIBRARY_PATH="$PWD/build/gpu_bundle${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export MILLSIM_SOURCE_DIR="$PWD"
threads=$(nproc)
status=0
{ date -u; nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv 2>&1 || true; echo "cpu threads: $threads"; } |
  tee "$out/machine.txt"
# A library the bundle lacks, or one built for a newer glibc than the image's, shows here first.
{ ldd --version | head -n 1; ldd build/tests/millsim_gpu_tests build/bench/millsim_bench | grep -E 'not found|version' || true; } |
  tee -a "$out/machine.txt"

stages=" ${GPU_STAGES:-tests ls1 dem sph ensemble coupled} "
want() { [[ "$stages" == *" $1 "* ]]; }

if want tests; then
echo "== GPU tests (CUDA vs OpenMP; MILLSIM_CUDA_SYNC=1: a fault names its kernel)"
MILLSIM_CUDA_SYNC=1 OMP_NUM_THREADS=$threads timeout "${TESTS_S:-200}" build/tests/millsim_gpu_tests \
  --gtest_output="json:$out/gpu_tests.json" 2>&1 | tee "$out/gpu_tests.txt" | grep -E '^\[|^T = |drift|Z/a|Skipped|device|coupled steps|largest difference'
tests_rc=${PIPESTATUS[0]}
if [ "$tests_rc" -ne 0 ]; then  # a failed test, a crash, or the time limit (124)
  echo "!! GPU tests exited with $tests_rc" | tee -a "$out/gpu_tests.txt"
  status=1
fi
# On the GPU machine a skipped GPU test is a failure (the skip message says why: driver, no device).
if grep -q '^\[  SKIPPED \]' "$out/gpu_tests.txt"; then
  echo "!! GPU tests were SKIPPED: no usable CUDA device (see the skip message above)" | tee -a "$out/gpu_tests.txt"
  status=1
fi
fi

bench() {  # name, seconds, filter, extra env
  local name=$1 secs=$2 filter=$3
  shift 3
  echo "== bench $name ($filter)"
  # The console lines go to a file as well: a run cut by its limit leaves no JSON, but what it
  # printed before stays.
  env OMP_NUM_THREADS="$threads" "$@" timeout "$secs" build/bench/millsim_bench --benchmark_filter="$filter" \
    --benchmark_out="$out/bench_$name.json" --benchmark_out_format=json 2>&1 | grep -vE '^\*\*\*' |
    tee -a "$out/bench_console.txt" | tail -n 20
}
# Issues 6 and 10: the LS1 case, 1 ms on both backends (the rate), then 52.5 ms on the GPU.
if want ls1; then
  bench ls1 "${LS1_S:-40}" 'BM_StirredLs1/1000/'
  bench ls1_full "${LS1_FULL_S:-100}" 'BM_StirredLs1/52500/1'
fi
# Issue 6, Done-when 2: the whole speed program of the full LS1 case (7 x 57.5 ms, ~4 min on an
# H200), its outputs packed into one archive (the device tool brings back at most 8 files).
# Not in the default stages: GPU_STAGES="tests ls1_program".
if want ls1_program; then
  # LS1_PROGRAM_END_US=287500: the first five levels only (1000 .. 3000 rpm, ~3.5 min).
  bench ls1_program "${LS1_PROGRAM_S:-400}" "BM_StirredLs1/${LS1_PROGRAM_END_US:-402500}/1" \
    MILLSIM_BENCH_OUT="$out/ls1_program"
  tar -C "$out" -czf "$out/ls1_program.tar.gz" ls1_program && rm -rf "$out/ls1_program"
fi
# Issue 5, Done-when 5: a whole case with its outputs (bench/bench_case_run.cpp), on request:
# GPU_STAGES=case CASE=ball_mill_500_wet.xml CASE_SET='time.end=4' (overrides ';'-separated),
# OUT/case.tar.gz; then compare its angle and slurry curve with the CPU run's.
if want case; then
  bench case "${CASE_S:-500}" 'BM_CaseRun/1' MILLSIM_BENCH_CASE="${CASE:-}" MILLSIM_BENCH_SET="${CASE_SET:-}" \
    MILLSIM_BENCH_OUT="$out/case"
  tar -C "$out" -czf "$out/case.tar.gz" case && rm -rf "$out/case"
fi
want dem && bench dem "${DEM_S:-60}" 'BM_DemScaling'
if want sph; then
  bench sph_double "${SPH_S:-70}" 'BM_SphScaling3d'
  bench sph_float "${SPH_F_S:-50}" 'BM_SphScaling3d/.*/1' MILLSIM_BENCH_FLOAT=1
fi
# Issue 10, Done-when 4: 18 drums (6 candidates x 300/400/500 mm) as one ensemble against the
# 300 mm drum alone, 2 s simulated each, on the GPU (the CPU side is in docs/performance.md).
want ensemble && bench ensemble "${ENS_S:-70}" 'BM_DrumEnsemble/./1' MILLSIM_ENSEMBLE_T="${ENSEMBLE_T:-2}"
# The paper's wet mill scaled to N particles (bench/bench_coupled.cpp); not the 195 329 of the
# case itself, measured on the CPU (docs/performance.md).
if want coupled; then
  bench coupled "${COUPLED_S:-40}" 'BM_CoupledScaling/(10000|100000|1000000)/'
  bench coupled_1e7 "${COUPLED_7_S:-40}" 'BM_CoupledScaling/10000000/'
fi

python3 - "$out" <<'EOF' | tee "$out/summary.txt"
import glob, json, os, sys
for path in sorted(glob.glob(os.path.join(sys.argv[1], "bench_*.json"))):
    try:
        runs = json.load(open(path))["benchmarks"]
    except Exception as e:  # a run cut by its time limit leaves no or partial JSON
        print(f"{os.path.basename(path)}: unreadable ({e})")
        continue
    for b in runs:
        if b.get("error_occurred"):
            print(f"{os.path.basename(path)} {b['name']}: skipped ({b.get('error_message', '')})")
            continue
        if "scenes" in b:  # BM_DrumEnsemble: one iteration is one whole run
            print(f"{os.path.basename(path)} {b['name']}: {b['scenes']:.0f} scene(s), {b['particles']:.0f} balls, "
                  f"{b['real_time']:.3g} {b['time_unit']} per run, {b['particle_steps_per_s']:.3g} particle-steps/s")
            continue
        if "wall_per_52_5ms_s" in b:  # BM_StirredLs1: one iteration is one whole run
            print(f"{os.path.basename(path)} {b['name']}: {b['particles']:.0f} beads, {b['steps']:.0f} steps, "
                  f"{b['simulated_s'] * 1e3:.3g} ms simulated in {b['run_wall_s']:.3g} s, "
                  f"52.5 ms -> {b['wall_per_52_5ms_s']:.3g} s, {b['particle_steps_per_s']:.3g} particle-steps/s")
            continue
        n = b.get("fluid") or b.get("particles")
        print(f"{os.path.basename(path)} {b['name']}: N = {n:.0f}, {b['real_time']:.3g} {b['time_unit']}/step, "
              f"{b.get('particle_steps_per_s', 0):.3g} particle-steps/s, {b.get('fluid_steps_per_s', 0):.3g} fluid-steps/s")
EOF
exit $status
