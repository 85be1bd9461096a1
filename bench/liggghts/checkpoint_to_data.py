#!/usr/bin/env python3
"""Turn a millsim checkpoint into a LIGGGHTS data file plus an include file of run variables.

The checkpoint is read with h5dump (hdf5-tools) so that no Python package beyond the standard
library is needed (h5py and numpy are not installed on the bench machine). Values are printed
with 17 significant digits so the LIGGGHTS state is the millsim state to the last bit.

Usage: checkpoint_to_data.py CHECKPOINT.h5 OUTDIR [--t-end 12] [--frames 100] [--frame-dt 0.08]
                             [--steps N] [--box XLO XHI YLO YHI ZLO ZHI]
--steps runs exactly N steps instead of up to --t-end; --box sets the (fixed) simulation box,
by default the one around the 300 mm drum.
Writes OUTDIR/balls.data (atom_style granular: Atoms and Velocities with angular velocities)
and OUTDIR/vars.in (dt, number of steps, first timestep, dump interval, first dumped frame).
"""
import argparse
import math
import os
import re
import subprocess


def h5(path, obj, attribute=False):
    """All numbers of a dataset or scalar attribute, as floats, via h5dump."""
    flag = "-a" if attribute else "-d"
    out = subprocess.run(["h5dump", "-m", "%.17g", flag, obj, path],
                         check=True, capture_output=True, text=True).stdout
    data = out.split("DATA {", 1)[1].split("}", 1)[0]
    data = re.sub(r"\(\d+(,\d+)*\):", " ", data)  # drop the "(index):" prefixes
    return [float(x) for x in data.replace(",", " ").split()]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("checkpoint")
    ap.add_argument("outdir")
    ap.add_argument("--t-end", type=float, default=12.0)
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--frame-dt", type=float, default=0.08)
    ap.add_argument("--steps", type=int, default=0, help="> 0: run this many steps (not to --t-end)")
    ap.add_argument("--box", type=float, nargs=6, default=[-0.16, 0.16, -0.16, 0.16, -0.01, 0.11])
    a = ap.parse_args()

    t0 = h5(a.checkpoint, "/time", True)[0]
    dt = h5(a.checkpoint, "/scalars/dt", True)[0]
    phi = h5(a.checkpoint, "/scalars/phi", True)[0]
    pos, vel, omg = (h5(a.checkpoint, "/reals/" + k) for k in ("pos", "vel", "omega"))
    rad, mass = h5(a.checkpoint, "/reals/radius"), h5(a.checkpoint, "/reals/mass")
    n = len(rad)
    assert len(pos) == len(vel) == len(omg) == 3 * n and len(mass) == n

    os.makedirs(a.outdir, exist_ok=True)
    with open(os.path.join(a.outdir, "balls.data"), "w") as f:
        f.write(f"millsim checkpoint {a.checkpoint} at t = {t0!r} s\n\n{n} atoms\n1 atom types\n\n")
        # Fixed box a little larger than the drum: every mesh node must stay inside it.
        f.write("%r %r xlo xhi\n%r %r ylo yhi\n%r %r zlo zhi\n\nAtoms\n\n" % tuple(a.box))
        for i in range(n):
            # granular: id type diameter density x y z. The density is taken from millsim's own
            # mass so both codes integrate exactly the same masses.
            rho = mass[i] / (4.0 / 3.0 * math.pi * rad[i] ** 3)
            f.write("%d 1 %.17g %.17g %.17g %.17g %.17g\n" % (i + 1, 2 * rad[i], rho, *pos[3 * i:3 * i + 3]))
        f.write("\nVelocities\n\n")
        for i in range(n):
            f.write("%d %.17g %.17g %.17g %.17g %.17g %.17g\n" % (i + 1, *vel[3 * i:3 * i + 3], *omg[3 * i:3 * i + 3]))

    # Time bookkeeping. LIGGGHTS dumps on timesteps that are multiples of the dump interval, so
    # the run starts at a timestep chosen to put the last step (t_end) on such a multiple; the
    # frames then sit at t_end, t_end - frame_dt, ... like millsim's (start + k frame_dt).
    nrun = a.steps if a.steps > 0 else round((a.t_end - t0) / dt)
    every = round(a.frame_dt / dt)
    step0 = (-nrun) % every
    first_frame = step0 + nrun - (a.frames - 1) * every
    with open(os.path.join(a.outdir, "vars.in"), "w") as f:
        f.write(f"# from {a.checkpoint}: t0 = {t0!r} s, drum angle {phi!r} rad, {n} balls\n")
        f.write(f"variable dt equal {dt!r}\nvariable nrun equal {nrun}\nvariable step0 equal {step0}\n")
        f.write(f"variable every equal {every}\nvariable first_frame equal {first_frame}\n")
    print(f"t0={t0!r} phi={phi!r} dt={dt!r} balls={n} nrun={nrun} step0={step0} every={every} "
          f"first_frame={first_frame}")


if __name__ == "__main__":
    main()
