#!/usr/bin/env bash
# Cross-code check: millsim and LIGGGHTS 3.8 run the 300 mm balls-only drum
# (cases/ball_mill_300_balls.xml) for t = 2..12 s from the same state, both on one core, and
# the angle of repose of both goes through millsim's own front-view pipeline.
#
#   bench/liggghts/run_compare.sh [RUN_DIR]      (default /tmp/millsim_liggghts)
#
# Environment: MILLSIM (default build/apps/millsim/millsim), LIGGGHTS (default: liggghts on
# PATH, installed with apt-get if missing), LIGGGHTS_WALLS = moving (default: every drum mesh
# turned by fix move/mesh) or axisym (only the lifters turn; see walls_axisym.in).
# Takes a few minutes. See bench/liggghts/README.md.
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
RUN=$(mkdir -p "${1:-/tmp/millsim_liggghts}" && cd "${1:-/tmp/millsim_liggghts}" && pwd)
MILLSIM=${MILLSIM:-$ROOT/build/apps/millsim/millsim}
CASE=$ROOT/cases/ball_mill_300_balls.xml
# Drum geometry from the case file, so the meshes and the LIGGGHTS box follow it.
attr() { sed -n "s/.*<$1 [^>]*$2=\"\([^\"]*\)\".*/\1/p" "$CASE" | head -n 1; }
DIAMETER=$(attr drum diameter)
LENGTH=$(attr drum length)
BOX=$(python3 -c "d, L = $DIAMETER, $LENGTH; r = d / 2 + 0.014; print(-r, r, -r, r, -0.01, L + 0.01)")

# Tools: LIGGGHTS from Debian (package liggghts), h5dump to read millsim's checkpoint.
if [ -z "${LIGGGHTS:-}" ] && ! command -v liggghts >/dev/null; then
  apt-get update -qq && apt-get install -y -q liggghts >"$RUN/apt.log"
fi
LIGGGHTS=${LIGGGHTS:-liggghts}
WALLS=${LIGGGHTS_WALLS:-moving}
command -v h5dump >/dev/null || apt-get install -y -q hdf5-tools >>"$RUN/apt.log"

# 1. millsim places and compacts the charge (t = 0..2 s). Keep a copy of the t = 2 s checkpoint:
#    the continued run below writes its own checkpoints into the same directory.
echo "[1/5] millsim t = 0..2 s (compaction)"
rm -rf "$RUN/millsim_t2" "$RUN/liggghts"
"$MILLSIM" run "$CASE" --set time.end=2 --out "$RUN/millsim_t2" -q --threads 1 >"$RUN/millsim_0_2.json"
cp "$RUN/millsim_t2/checkpoint.h5" "$RUN/checkpoint_t2.h5"

# 2. The same state for LIGGGHTS: data file, run variables and drum meshes at the drum angle
#    of the checkpoint.
echo "[2/5] LIGGGHTS input from the t = 2 s checkpoint"
mkdir -p "$RUN/liggghts"
CONV=$(python3 "$HERE/checkpoint_to_data.py" "$RUN/checkpoint_t2.h5" "$RUN/liggghts" --box $BOX)
echo "      $CONV"
PHI=$(sed -n 's/.*phi=\([^ ]*\).*/\1/p' <<<"$CONV")
FIRST_FRAME=$(sed -n 's/.*first_frame=\([^ ]*\).*/\1/p' <<<"$CONV")
python3 "$HERE/make_meshes.py" "$RUN/liggghts/meshes" --phi="$PHI" --radius "$(python3 -c "print($DIAMETER / 2)")" \
  --length "$LENGTH"
cp "$HERE/in.drum" "$HERE"/walls_*.in "$RUN/liggghts/"

# 3. millsim continues from the checkpoint (t = 2..12 s). One simulation at a time, one thread.
echo "[3/5] millsim t = 2..12 s"
"$MILLSIM" run "$CASE" --restart "$RUN/millsim_t2/checkpoint.h5" --out "$RUN/millsim_t2" -q --threads 1 \
  >"$RUN/millsim.json"

# 4. LIGGGHTS, serial (no mpirun: a single process is its own MPI world).
echo "[4/5] LIGGGHTS t = 2..12 s (walls: $WALLS)"
(cd "$RUN/liggghts" && "$LIGGGHTS" -var walls "$WALLS" -in in.drum -log log.liggghts -echo none >screen.txt)

# 5. LIGGGHTS angle through millsim's pipeline, from the last 100 frames (t = 4.08..12 s, the
#    frame times millsim uses).
echo "[5/5] angle of repose of the LIGGGHTS dumps"
"$MILLSIM" angle-from-dumps --dumps "$RUN"/liggghts/dumps/dump.*.txt --diameter "$DIAMETER" --pixels-per-mm 2 \
  --from-timestep "$FIRST_FRAME" --out "$RUN/liggghts/angle" >"$RUN/liggghts_angle.json"

python3 - "$RUN" "$WALLS" <<'EOF'
import json, re, sys
run, walls_mode = sys.argv[1], sys.argv[2]
m = json.load(open(f"{run}/millsim.json"))
ms = json.load(open(f"{run}/millsim_t2/summary.json"))
m0 = json.load(open(f"{run}/millsim_0_2.json"))
la = json.load(open(f"{run}/liggghts_angle.json"))
log = open(f"{run}/liggghts/log.liggghts").read()
version = open(f"{run}/liggghts/screen.txt").readline().strip()
loop = re.search(r"Loop time of ([\d.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
modify = re.search(r"Modfy time \(%\) = [\d.eE+-]+ \(([\d.eE+-]+)\)", log)
walls = sum(float(x) for x in re.findall(r"Fix \S+ (?:wall/gran|move/mesh|neighlist/mesh) time \(%\) = \S+ \((\S+)\)", log))
vars_ = dict(re.findall(r"variable (\w+) equal (\S+)", open(f"{run}/liggghts/vars.in").read()))

n = ms["particles"]["dem_spheres"]
m_steps = ms["steps"] - m0["steps"]  # the restarted run's summary counts the steps from t = 0
m_sim = m_steps * ms["dt_s"]
l_wall, procs, l_steps, l_n = float(loop[1]), int(loop[2]), int(loop[3]), int(loop[4])
l_sim = l_steps * float(vars_["dt"])
rows = [  # code, angle, stderr, wall for the run, simulated s, particle-steps/s/core
    ("millsim", m["angle_of_repose_deg"], ms.get("angle_of_repose_stderr_deg"), m["wall_time_s"], m_sim, n * m_steps / m["wall_time_s"]),
    ("LIGGGHTS", la["angle_deg"], la["stderr_deg"], l_wall, l_sim, l_n * l_steps / l_wall / procs),
]
f = lambda x, p: "n/a" if x is None else f"{x:.{p}f}"
print(f"\n{version}")
print(f"balls: millsim {n}, LIGGGHTS {l_n}; steps: millsim {m_steps}, LIGGGHTS {l_steps}; "
      f"LIGGGHTS frames for the angle: {la['frames']}")
print(f"LIGGGHTS walls: {walls_mode}; Modify: {modify[1] if modify else 'n/a'} % of its loop time "
      f"(of which wall/gran + move/mesh + mesh neighbour lists: {walls:.1f} %)\n")
print(f"{'code':10} {'angle [deg]':>11} {'stderr':>7} {'wall 10 s [s]':>14} {'wall s/sim s':>13} {'particle-steps/s/core':>22}")
for c, a, e, w, s, ps in rows:
    print(f"{c:10} {f(a, 2):>11} {f(e, 2):>7} {w:14.2f} {w / s:13.3f} {ps:22.4g}")
(_, a1, e1, w1, s1, p1), (_, a2, e2, w2, s2, p2) = rows
ratio = lambda x, y: "n/a" if x is None or y is None else f"{x / y:.3f}"
print(f"{'millsim/L':10} {ratio(a1, a2):>11} {ratio(e1, e2):>7} {ratio(w1, w2):>14} "
      f"{ratio(w1 / s1, w2 / s2):>13} {ratio(p1, p2):>22}")
EOF
