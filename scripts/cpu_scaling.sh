#!/usr/bin/env bash
# CPU thread scaling at N >= 1e5 (issue 10): throughput on 2 OpenMP threads against 1 thread for
#   - DEM: bench_dem's drum at 200 000 balls (BM_DemDrumStep/200000),
#   - SPH: the 3D dam break at dp = a/40 (128 000 fluid particles, BM_SphDamBreak3dFine),
#   - the full LS1 stirred mill (128 000 beads, 300 steps from its lattice, `millsim run`).
# Run on an otherwise idle machine (every core is used). Usage: scripts/cpu_scaling.sh [THREADS]
# (default 2: compares 1 and THREADS). Needs build/ (scripts/build.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
n=${1:-2}
bench=$root/build/bench/millsim_bench
cli=$root/build/apps/millsim/millsim
out=$(mktemp -d)
rate() {  # benchmark filter, threads -> particle_steps_per_s
  OMP_NUM_THREADS=$2 "$bench" --benchmark_filter="$1" --benchmark_min_time=3 --benchmark_format=json 2>/dev/null |
    python3 -c 'import json, sys; b = json.load(sys.stdin)["benchmarks"][0]; print("%.4g" % b["particle_steps_per_s"])'
}
ls1() {  # threads -> particle-steps/s of 300 LS1 steps (at k_n = 1e5 N/m, dt 0.62 us, as measured before 2026-12-07)
  "$cli" run "$root/cases/stirred_mill_ls1.xml" --out "$out/ls1_$1" -q --threads "$1" --set time.end=1.85e-4 \
    --set dem.linear_stiffness=1e5 --set dem.skin=0.2 >/dev/null
  python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); print("%.4g" % (j["steps"] * j["stirred"]["beads"] / j["wall_time_s"]))' \
    "$out/ls1_$1/summary.json"
}
printf '%-44s %14s %14s %8s\n' "case" "1 thread" "$n threads" "speedup"
for spec in "DEM drum, 200 000 balls|BM_DemDrumStep/200000/0" "SPH 3D dam break, 128 000 fluid (dp = a/40)|BM_SphDamBreak3dFine"; do
  name=${spec%%|*} filter=${spec##*|}
  r1=$(rate "$filter" 1) rn=$(rate "$filter" "$n")
  printf '%-44s %14s %14s %8.2f\n' "$name" "$r1" "$rn" "$(python3 -c "print($rn / $r1)")"
done
r1=$(ls1 1) rn=$(ls1 "$n")
printf '%-44s %14s %14s %8.2f\n' "stirred LS1, 128 000 beads, 300 steps" "$r1" "$rn" "$(python3 -c "print($rn / $r1)")"
rm -rf "$out"
