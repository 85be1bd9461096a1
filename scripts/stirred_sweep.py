#!/usr/bin/env python3
"""Calibration sweeps of the stirred mill, as seed 004 does them (section 4.1):

  friction: run the case dry for each mu_c, compare the net power per speed with measured
            values (CSV rpm,power_W), sum of squared differences per mu_c, and the minimum of
            the parabola through the three lowest SSEs (or the lowest point at an end).
  viscosity: run the case at one speed for each eta_f,sim, and interpolate linearly the eta at
            which the simulated net power equals a measured one (the seed: 2500 rpm).

Each run is `millsim run CASE --set ...` (one at a time, --threads as given); results go to
OUT/sweep.csv. Standard library only.

  scripts/stirred_sweep.py friction cases/stirred_mill_ls1_small.xml --values 0.2 0.3 0.4 \
      --measured measured_dry.csv --out /tmp/sweep_mu
  scripts/stirred_sweep.py viscosity cases/stirred_mill_ls1_small.xml --values 0 0.5 1 \
      --rpm 2500 --target-power 400 --friction 0.3 --out /tmp/sweep_eta
"""
import argparse
import csv
import json
import os
import subprocess
import sys


def run_case(millsim, case, out, sets, threads):
    cmd = [millsim, "run", case, "--out", out, "-q", "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["stirred"]["levels"]


def read_measured(path):
    with open(path) as f:
        return {float(r["rpm"]): float(r["power_W"]) for r in csv.DictReader(f)}


def parabola_minimum(xs, ys):
    """Minimum of the parabola through the three lowest points (x sorted), or the lowest point."""
    k = min(range(len(ys)), key=lambda i: ys[i])
    if k == 0 or k == len(ys) - 1:
        return xs[k]
    (x0, x1, x2), (y0, y1, y2) = xs[k - 1:k + 2], ys[k - 1:k + 2]
    den = (x0 - x1) * (x0 - x2) * (x1 - x2)
    a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den
    b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den
    return -b / (2 * a) if a > 0 else xs[k]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["friction", "viscosity"])
    ap.add_argument("case")
    ap.add_argument("--values", type=float, nargs="+", required=True)
    ap.add_argument("--measured", help="friction: CSV with columns rpm,power_W (net power)")
    ap.add_argument("--rpm", type=float, default=2500.0, help="viscosity: the speed of the comparison")
    ap.add_argument("--target-power", type=float, help="viscosity: measured net power at --rpm [W]")
    ap.add_argument("--friction", type=float, default=0.3, help="viscosity: mu_c of the wet runs")
    ap.add_argument("--set", action="append", default=[], help="extra --set overrides for every run")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--millsim", default=os.environ.get("MILLSIM", "build/apps/millsim/millsim"))
    ap.add_argument("--out", default="/tmp/millsim_stirred_sweep")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    if a.mode == "friction":
        if not a.measured:
            sys.exit("friction mode needs --measured rpm,power_W CSV")
        measured = read_measured(a.measured)
        speeds = " ".join("%g" % r for r in sorted(measured))
        sse = []
        for mu in a.values:
            levels = run_case(a.millsim, a.case, os.path.join(a.out, "mu_%g" % mu),
                              a.set + ["dem.friction=%g" % mu, "lubrication.viscosity=0", "stirrer.speeds_rpm=" + speeds],
                              a.threads)
            e = sum((lv["net_power_W"] - measured[lv["rpm"]]) ** 2 for lv in levels)
            sse.append(e)
            rows += [{"mu_c": mu, "rpm": lv["rpm"], "net_power_W": lv["net_power_W"],
                      "measured_W": measured[lv["rpm"]], "sse_W2": e} for lv in levels]
        best = parabola_minimum(a.values, sse)
        print("mu_c SSE: " + ", ".join("%g: %.4g" % (m, e) for m, e in zip(a.values, sse)))
        print("best mu_c = %.4g" % best)
    else:
        if a.target_power is None:
            sys.exit("viscosity mode needs --target-power")
        powers = []
        for eta in a.values:
            levels = run_case(a.millsim, a.case, os.path.join(a.out, "eta_%g" % eta),
                              a.set + ["dem.friction=%g" % a.friction, "lubrication.viscosity=%g" % eta,
                                       "stirrer.speeds_rpm=%g" % a.rpm], a.threads)
            powers.append(levels[-1]["net_power_W"])
            rows.append({"eta_Pa_s": eta, "rpm": a.rpm, "net_power_W": powers[-1], "measured_W": a.target_power})
        best = None
        for (e0, p0), (e1, p1) in zip(zip(a.values, powers), zip(a.values[1:], powers[1:])):
            if (p0 - a.target_power) * (p1 - a.target_power) <= 0 and p1 != p0:
                best = e0 + (a.target_power - p0) * (e1 - e0) / (p1 - p0)
                break
        print("P(eta): " + ", ".join("%g: %.4g W" % (e, p) for e, p in zip(a.values, powers)))
        print("eta_f,sim = %s" % ("%.4g Pa s" % best if best is not None else "outside the swept range"))
    with open(os.path.join(a.out, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
