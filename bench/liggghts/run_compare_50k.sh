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
# setup, see walls_*.in), LIGGGHTS_SKIN (neighbour skin [m], default millsim's: 0.2 r_min),
# CHECKPOINT (a checkpoint of drum_50k.xml to start from instead of making one: skips step 1,
# which takes about 32 min), MILLSIM_SORTED=1 (one more millsim run from a copy of the
# checkpoint with the balls renumbered in space, see sort_checkpoint.py).
# Run nothing else on the machine meanwhile: both codes are timed.
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
RUN=$(mkdir -p "${1:-/tmp/millsim_liggghts_50k}" && cd "${1:-/tmp/millsim_liggghts_50k}" && pwd)
MILLSIM=${MILLSIM:-$ROOT/build/apps/millsim/millsim}
CASE=$HERE/drum_50k.xml
STEPS=${STEPS:-3000}
WALLS=${LIGGGHTS_WALLS:-moving axisym}

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
read -r D L NLIFT H W DMIN < <(python3 - "$CASE" <<'EOF'
import sys, xml.etree.ElementTree as ET
c = ET.parse(sys.argv[1]).getroot(); d = c.find("drum"); l = d.find("lifters")
print(d.get("diameter"), d.get("length"), l.get("count"), l.get("height"), l.get("width"), c.find("charge").get("min_size"))
EOF
)
SKIN=${LIGGGHTS_SKIN:-$(python3 -c "print(f'{0.1 * $DMIN:.6g}')")}  # millsim's skin: 0.2 x smallest radius
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

# 3. millsim: STEPS steps from the checkpoint (the loop stops at t >= end - dt/2). With
#    MILLSIM_SORTED=1 a second run starts from a copy whose balls are renumbered in space
#    (sort_checkpoint.py, needs python3-h5py): same physics, shows the cost of cache misses.
T_END=$(python3 -c "print(repr($T_START + $STEPS * $DT))")
rm -rf "$RUN/millsim_run" "$RUN/millsim_sorted" && mkdir -p "$RUN/millsim_run"
cp "$RUN/checkpoint_start.h5" "$RUN/millsim_run/checkpoint.h5"
if [ "${MILLSIM_SORTED:-0}" = 1 ]; then
  mkdir -p "$RUN/millsim_sorted"
  /usr/bin/python3 "$HERE/sort_checkpoint.py" "$RUN/checkpoint_start.h5" "$RUN/millsim_sorted/checkpoint.h5" >/dev/null
fi
for d in millsim_run millsim_sorted; do
  [ -d "$RUN/$d" ] || continue
  echo "[3/4] millsim ($d), $STEPS steps from t = $T_START s"
  "$MILLSIM" run "$CASE" --restart "$RUN/$d/checkpoint.h5" --out "$RUN/$d" -q --threads 1 \
    --set time.end="$T_END" >"$RUN/$d.json"
done

# 4. LIGGGHTS, serial, once per wall setup.
for w in $WALLS; do
  echo "[4/4] LIGGGHTS, $STEPS steps, walls $w, skin $SKIN m"
  (cd "$RUN/liggghts" && "$LIGGGHTS" -var walls "$w" -var rpm "$RPM" -var skin "$SKIN" -in in.bench \
     -log "log.$w" -echo none >"screen.$w.txt")
done

python3 - "$RUN" "$STEPS" $WALLS <<'EOF'
import json, os, re, subprocess, sys
run, steps, setups = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
# The restarted runs' summaries count the steps from t = 0: subtract those of the checkpoint.
h5 = subprocess.run(["h5dump", "-a", "/step", f"{run}/checkpoint_start.h5"], capture_output=True, text=True).stdout
step_start = int(re.search(r"\(0\): (\d+)", h5)[1])
rows, notes = [], []
for d, label in (("millsim_run", "millsim (--threads 1)"), ("millsim_sorted", "millsim, sorted input")):
    if not os.path.exists(f"{run}/{d}/summary.json"):
        continue
    ms = json.load(open(f"{run}/{d}/summary.json"))
    n, m_steps, wall = ms["particles"]["dem_spheres"], ms["steps"] - step_start, ms["wall_time_s"]
    rows.append((label, n, m_steps, wall, n * m_steps / wall))
    notes.append(f"{label}: {m_steps} steps of {ms['dt_s']:.6g} s (summary.json: {ms['steps']} from t = 0), "
                 f"{ms['neighbour_rebuilds']} neighbour rebuilds" + ("" if m_steps == steps else "  WARNING: not STEPS"))
for w in setups:
    log = open(f"{run}/liggghts/log.{w}").read()
    loop = re.search(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    wall, procs, l_steps, l_n = float(loop[1]), int(loop[2]), int(loop[3]), int(loop[4])
    rows.append((f"LIGGGHTS, walls {w}", l_n, l_steps, wall, l_n * l_steps / wall / procs))
    pct = {k: float(v) for k, v in re.findall(r"^(Pair|Neigh|Modfy|Other) +time \(%\) = \S+ \((\S+)\)", log, re.M)}
    fixes = {}
    for kind, p in re.findall(r"^Fix \S+ (\S+) time \(%\) = \S+ \((\S+)\)", log, re.M):
        fixes[kind] = fixes.get(kind, 0.0) + float(p)
    top = ", ".join(f"{k} {v:.1f}" for k, v in sorted(fixes.items(), key=lambda kv: -kv[1])[:4])
    builds = re.search(r"Neighbor list builds = (\d+)", log)
    notes.append(f"LIGGGHTS walls {w}: Pair {pct.get('Pair', 0):.1f} %, Modify {pct.get('Modfy', 0):.1f} % ({top}), "
                 f"Neigh {pct.get('Neigh', 0):.1f} %, Other {pct.get('Other', 0):.1f} % of {wall:.2f} s; "
                 f"{builds[1] if builds else '?'} neighbour builds")
m_rate = rows[0][4]
if setups:
    print("\n" + open(f"{run}/liggghts/screen.{setups[0]}.txt").readline().strip())
print(f"{'code':26} {'particles':>9} {'steps':>6} {'wall [s]':>9} {'particle-steps/s/core':>22} {'millsim/this':>12}")
for label, n, st, wall, rate in rows:
    print(f"{label:26} {n:9d} {st:6d} {wall:9.2f} {rate:22.4g} {m_rate / rate:12.2f}")
print("\n" + "\n".join(notes))
EOF
