#!/usr/bin/env bash
# Throughput of a stirred-mill slice, millsim vs LIGGGHTS 3.8, serial, on this machine.
# millsim: cases/stirred_mill_ls1_small.xml with the LS1 beads (1.8 mm, lattice-filled slice) at
# 2000 rpm; LIGGGHTS: in.stirred (same chamber, stirrer without holes, same beads and time step,
# gran/hooke/history). Both report particle-steps per second on one core.
# Usage: bench/liggghts/stirred/run_stirred_bench.sh [RUN_DIR] [STEPS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
run=${1:-/tmp/millsim_liggghts_stirred}
steps=${2:-2000}
millsim=${MILLSIM:-$root/build/apps/millsim/millsim}
mkdir -p "$run"
python3 "$here/make_stirrer_meshes.py" "$run/meshes"
cp "$here/in.stirred" "$run/"
dt=6.0e-7
# millsim: the slice with 1.8 mm beads, fixed dt, ramp 0 (starts at 2000 rpm), STEPS steps.
hold=$(python3 -c "print($steps * $dt)")
"$millsim" run "$root/cases/stirred_mill_ls1_small.xml" --out "$run/millsim" -q --threads 1 \
  --set beads.diameter=0.0018 --set beads.count=${BEADS:-29000} --set time.dt=fixed --set time.dt_fixed=$dt \
  --set stirrer.speeds_rpm=2000 --set stirrer.ramp=0 --set stirrer.hold=$hold --set output.series_every=1 \
  --set collisions.sample_every=1 >/dev/null
python3 - "$run/millsim/summary.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
ps = j["steps"] * j["stirred"]["beads"] / j["wall_time_s"]
print("millsim: %d beads, %d steps, %.2f s wall, %.3g particle-steps/s/core" % (j["stirred"]["beads"], j["steps"], j["wall_time_s"], ps))
PY
cd "$run"
liggghts -in in.stirred -var nrun "$steps" -var dt $dt > liggghts.log
python3 - liggghts.log "$steps" <<'PY'
import re, sys
log = open(sys.argv[1]).read()
atoms = int(re.search(r"Created (\d+) atoms", log).group(1))
loop = float(re.search(r"Loop time of ([0-9.eE+-]+)", log).group(1))
steps = int(sys.argv[2])
print("LIGGGHTS: %d beads, %d steps, %.2f s loop, %.3g particle-steps/s/core" % (atoms, steps, loop, atoms * steps / loop))
PY
