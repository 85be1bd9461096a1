#!/usr/bin/env bash
# Throughput of a stirred-mill slice, millsim vs LIGGGHTS 3.8, serial, on this machine.
# Both codes start from the same kind of state: every site of an FCC lattice of nearest-neighbour
# distance LF x 1.8 mm in the free space of the slice (LF > 1: beads apart, the bed settles and is
# sheared by the disk during the run), the stirrer at 2000 rpm from the start, the same time step,
# the same chamber and plain disk (millsim: hole_count=0), gran/hooke/history-equivalent contacts.
# millsim: cases/stirred_mill_ls1_small.xml with the LS1 beads; LIGGGHTS: in.stirred. Each prints
# particle-steps per second on one core and the bead-bead contacts per bead at the end, so that a
# difference in contact density (which dominates the cost) shows. The timed STEPS follow an
# untimed lead-in of SETTLE steps (default 16 x STEPS: 48 ms at the default 5000 steps, enough for
# the bed to collapse and be sheared), so the throughput is that of a stirred dense bed, not of a
# lattice: LIGGGHTS runs the lead-in as its own `run`; millsim's series.csv has the wall time
# (rows every STEPS steps), and its throughput is taken over the last row interval.
# Usage: bench/liggghts/stirred/run_stirred_bench.sh [RUN_DIR] [STEPS]
#        env: LF (lattice spacing / bead diameter, default 1.02), SETTLE (lead-in steps),
#        MILLSIM_ARGS (more millsim options, e.g. "--precision float"), THREADS (millsim's, default 1),
#        REUSE_LIGGGHTS=1 (keep RUN_DIR/liggghts.log from an earlier run of the same settings),
#        STATS=1 (millsim keeps its Beinert collision statistics; default off, as LIGGGHTS keeps none)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
run=${1:-/tmp/millsim_liggghts_stirred}
steps=${2:-5000}
settle=${SETTLE:-$((16 * steps))}
lf=${LF:-1.02}
millsim=${MILLSIM:-$root/build/apps/millsim/millsim}
mkdir -p "$run"
python3 "$here/make_stirrer_meshes.py" "$run/meshes"
cp "$here/in.stirred" "$run/"
dt=6.0e-7
[ "${REUSE_LIGGGHTS:-0}" = 1 ] && [ -f "$run/liggghts.log" ] ||
  (cd "$run" && liggghts -in in.stirred -var nrun "$steps" -var nsettle "$settle" -var dt $dt -var lf "$lf" > liggghts.log)
atoms=$(sed -n 's/^Created \([0-9]*\) atoms.*/\1/p' "$run/liggghts.log" | head -1)
# millsim: as many beads as LIGGGHTS placed (its lattice origin differs slightly), fixed dt,
# ramp 0 (starts at 2000 rpm), SETTLE + STEPS steps, a series row every STEPS steps.
hold=$(python3 -c "print(($settle + $steps) * $dt)")
every=$(python3 -c "print(repr($steps * $dt))")
"$millsim" run "$root/cases/stirred_mill_ls1_small.xml" --out "$run/millsim" -q --threads ${THREADS:-1} ${MILLSIM_ARGS:-} \
  --set beads.diameter=0.0018 --set beads.count=${BEADS:-$atoms} --set beads.lattice_factor=$lf \
  --set stirrer.hole_count=0 --set collisions.enabled=$([ "${STATS:-0}" = 1 ] && echo true || echo false) \
  --set time.dt=fixed --set time.dt_fixed=$dt \
  --set stirrer.speeds_rpm=2000 --set stirrer.ramp=0 --set stirrer.hold=$hold --set output.series_every=$every \
  --set collisions.sample_every=1 >/dev/null
python3 - "$run/millsim/summary.json" "$run/millsim/series.csv" "$steps" <<'PY'
import csv, json, sys
j = json.load(open(sys.argv[1]))
s = j["stirred"]
rows = list(csv.DictReader(open(sys.argv[2])))
steps = int(sys.argv[3])
wall = float(rows[-1]["wall_time_s"]) - float(rows[-2]["wall_time_s"])
ps = steps * s["beads"] / wall / j["threads"]
print("millsim (%s, %d thread(s)): %d beads, last %d of %d steps, %.2f s wall, %.3g particle-steps/s/core, %d neighbour builds in all, "
      "%.2f contacts per bead at the end" % (j["precision"], j["threads"], s["beads"], steps, j["steps"], wall, ps, s["neighbour_rebuilds"],
                                             s["coordination_number_end"]))
PY
python3 - "$run/liggghts.log" "$steps" <<'PY'
import re, sys
log = open(sys.argv[1]).read()
atoms = int(re.search(r"Created (\d+) atoms", log).group(1))
# The timed run is the last `run`: its loop time, neighbour builds and last thermo row
# (step atoms ke contacts).
loop = float(re.findall(r"Loop time of ([0-9.eE+-]+)", log)[-1])
builds = int(re.findall(r"Neighbor list builds = (\d+)", log)[-1])
rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)\s*$", log.split("Loop time")[-2], re.M)
contacts = float(rows[-1][3]) / atoms if rows else float("nan")
steps = int(sys.argv[2])
print("LIGGGHTS: %d beads, %d steps, %.2f s loop, %.3g particle-steps/s/core, %d neighbour builds, "
      "%.2f contacts per bead at the end" % (atoms, steps, loop, atoms * steps / loop, builds, contacts))
PY
