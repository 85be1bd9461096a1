#!/usr/bin/env bash
# Throughput side by side: millsim and LIGGGHTS 3.8 on ~49 000 balls of 3 mm in a 200 mm drum
# with 8 lifters turning at 30 % of critical (bench/liggghts/drum_50k.xml), the issue's
# "particle-steps/s per core on a 50k-particle granular case". Both codes start from the same
# millsim checkpoint (dense bed, drum turning) and run the same number of steps at millsim's dt
# on one core each.
#
#   bench/liggghts/run_compare_50k.sh [RUN_DIR]      (default /tmp/millsim_liggghts_50k)
#
# Environment: MILLSIM (default build/apps/millsim/millsim), LIGGGHTS (default liggghts),
# STEPS (default 3000), LIGGGHTS_WALLS (default "moving axisym": one LIGGGHTS run per wall
# setup, see walls_*.in), LIGGGHTS_SKIN (neighbour skin [m], default 0.0015 = one radius),
# CHECKPOINT (a checkpoint of drum_50k.xml to start from instead of making one: skips step 1,
# which takes about 15 min). Run nothing else on the machine meanwhile: both codes are timed.
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
RUN=$(mkdir -p "${1:-/tmp/millsim_liggghts_50k}" && cd "${1:-/tmp/millsim_liggghts_50k}" && pwd)
MILLSIM=${MILLSIM:-$ROOT/build/apps/millsim/millsim}
CASE=$HERE/drum_50k.xml
STEPS=${STEPS:-3000}
WALLS=${LIGGGHTS_WALLS:-moving axisym}
SKIN=${LIGGGHTS_SKIN:-0.0015}

if [ -z "${LIGGGHTS:-}" ] && ! command -v liggghts >/dev/null; then
  apt-get update -qq && apt-get install -y -q liggghts >"$RUN/apt.log"
fi
LIGGGHTS=${LIGGGHTS:-liggghts}
command -v h5dump >/dev/null || apt-get install -y -q hdf5-tools >>"$RUN/apt.log"

# 1. millsim places the balls, compacts and settles them and starts the drum (t = 0..0.35 s).
if [ -z "${CHECKPOINT:-}" ]; then
  echo "[1/4] millsim t = 0..0.35 s (placement, compaction, settling, drum starts at 0.3 s)"
  rm -rf "$RUN/millsim_t0"
  T0=$(date +%s)
  "$MILLSIM" run "$CASE" --out "$RUN/millsim_t0" -q --threads 1 >"$RUN/millsim_0.json"
  echo "      took $(( $(date +%s) - T0 )) s"
  cp "$RUN/millsim_t0/checkpoint.h5" "$RUN/checkpoint_start.h5"
  cp "$RUN/millsim_t0/summary.json" "$RUN/summary_start.json"
else
  echo "[1/4] starting from $CHECKPOINT"
  [ "$CHECKPOINT" -ef "$RUN/checkpoint_start.h5" ] || cp "$CHECKPOINT" "$RUN/checkpoint_start.h5"
  # The summary of the run that wrote it, if it lies next to it (for the drum speed).
  [ -f "$(dirname "$CHECKPOINT")/summary.json" ] && { [ "$(dirname "$CHECKPOINT")/summary.json" -ef "$RUN/summary_start.json" ] ||
    cp "$(dirname "$CHECKPOINT")/summary.json" "$RUN/summary_start.json"; }
fi

# 2. LIGGGHTS input: data file and vars.in (STEPS steps at millsim's dt), drum meshes at the
#    checkpoint's drum angle, drum speed from millsim's summary (critical_fraction -> rpm).
echo "[2/4] LIGGGHTS input from the checkpoint"
rm -rf "$RUN/liggghts" && mkdir -p "$RUN/liggghts"
read -r D L NLIFT H W < <(python3 - "$CASE" <<'EOF'
import sys, xml.etree.ElementTree as ET
d = ET.parse(sys.argv[1]).getroot().find("drum"); l = d.find("lifters")
print(d.get("diameter"), d.get("length"), l.get("count"), l.get("height"), l.get("width"))
EOF
)
RPM=$(python3 -c 'import json, math, sys; print(json.load(open(sys.argv[1]))["omega_rad_s"] * 30 / math.pi)' \
  "$RUN/summary_start.json")
BOX=$(python3 -c "r = $D / 2 + 0.01; print(-r, r, -r, r, -0.01, $L + 0.01)")
CONV=$(python3 "$HERE/checkpoint_to_data.py" "$RUN/checkpoint_start.h5" "$RUN/liggghts" --steps "$STEPS" --box $BOX)
echo "      $CONV rpm=$RPM"
PHI=$(sed -n 's/.*phi=\([^ ]*\).*/\1/p' <<<"$CONV")
T_START=$(sed -n 's/^t0=\([^ ]*\).*/\1/p' <<<"$CONV")
DT=$(sed -n 's/.* dt=\([^ ]*\).*/\1/p' <<<"$CONV")
python3 "$HERE/make_meshes.py" "$RUN/liggghts/meshes" --phi="$PHI" --radius "$(python3 -c "print($D / 2)")" \
  --length "$L" --lifters "$NLIFT" --lifter-height "$H" --lifter-width "$W"
cp "$HERE/in.bench" "$HERE"/walls_*.in "$RUN/liggghts/"

# 3. millsim: STEPS steps from the checkpoint (the loop stops at t >= end - dt/2).
echo "[3/4] millsim, $STEPS steps from t = $T_START s"
rm -rf "$RUN/millsim_run" && mkdir -p "$RUN/millsim_run"
cp "$RUN/checkpoint_start.h5" "$RUN/millsim_run/checkpoint.h5"
T_END=$(python3 -c "print(repr($T_START + $STEPS * $DT))")
"$MILLSIM" run "$CASE" --restart "$RUN/millsim_run/checkpoint.h5" --out "$RUN/millsim_run" -q --threads 1 \
  --set time.end="$T_END" >"$RUN/millsim.json"

# 4. LIGGGHTS, serial, once per wall setup.
for w in $WALLS; do
  echo "[4/4] LIGGGHTS, $STEPS steps, walls $w, skin $SKIN m"
  (cd "$RUN/liggghts" && "$LIGGGHTS" -var walls "$w" -var rpm "$RPM" -var skin "$SKIN" -in in.bench \
     -log "log.$w" -echo none >"screen.$w.txt")
done

python3 - "$RUN" "$STEPS" $WALLS <<'EOF'
import json, re, subprocess, sys
run, steps, setups = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
ms = json.load(open(f"{run}/millsim_run/summary.json"))
n, m_wall = ms["particles"]["dem_spheres"], ms["wall_time_s"]
# The restarted run's summary counts the steps from t = 0: subtract those of the checkpoint.
h5 = subprocess.run(["h5dump", "-a", "/step", f"{run}/checkpoint_start.h5"], capture_output=True, text=True).stdout
m_steps = ms["steps"] - int(re.search(r"\(0\): (\d+)", h5)[1])
m_rate = n * m_steps / m_wall
if m_steps != steps:
    print(f"WARNING: millsim ran {m_steps} steps, not {steps}")
print(f"\nmillsim: {n} balls, {m_steps} steps of {ms['dt_s']:.6g} s (steps in summary.json: {ms['steps']}), "
      f"neighbour rebuilds (whole run): {ms['neighbour_rebuilds']}")
print(f"{'code':26} {'particles':>9} {'steps':>6} {'wall [s]':>9} {'particle-steps/s/core':>22} {'millsim/this':>12}")
print(f"{'millsim (--threads 1)':26} {n:9d} {m_steps:6d} {m_wall:9.2f} {m_rate:22.4g} {'':>12}")
shares = []
for w in setups:
    log = open(f"{run}/liggghts/log.{w}").read()
    loop = re.search(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    wall, procs, l_steps, l_n = float(loop[1]), int(loop[2]), int(loop[3]), int(loop[4])
    pct = {k: float(v) for k, v in re.findall(r"^(Pair|Neigh|Comm|Outpt|Modfy|Other) +time \(%\) = \S+ \((\S+)\)", log, re.M)}
    fixes = {}
    for kind, p in re.findall(r"^Fix \S+ (\S+) time \(%\) = \S+ \((\S+)\)", log, re.M):
        fixes[kind] = fixes.get(kind, 0.0) + float(p)
    rate = l_n * l_steps / wall / procs
    print(f"{'LIGGGHTS, walls ' + w:26} {l_n:9d} {l_steps:6d} {wall:9.2f} {rate:22.4g} {m_rate / rate:12.2f}")
    top = ", ".join(f"{k} {v:.1f}" for k, v in sorted(fixes.items(), key=lambda kv: -kv[1])[:4])
    shares.append(f"LIGGGHTS walls {w}: Pair {pct.get('Pair', 0):.1f} %, Modify {pct.get('Modfy', 0):.1f} % "
                  f"({top}), Neigh {pct.get('Neigh', 0):.1f} %, Other {pct.get('Other', 0):.1f} % of {wall:.2f} s")
print("\n" + "\n".join(shares))
EOF
