#!/usr/bin/python3
"""Diagnostic: reorder the balls of a millsim checkpoint spatially (bin order, as LAMMPS/LIGGGHTS
sort their atoms every 1000 steps), so that neighbours in space are neighbours in memory.

millsim keeps the balls in placement order (random in space); a restart from the sorted copy
shows how much of its time goes to cache misses. The state is the same up to the numbering:
partner ids in the contact history are renumbered too.
Needs h5py and numpy (Debian: apt-get install python3-h5py; run with /usr/bin/python3).

Usage: sort_checkpoint.py IN.h5 OUT.h5 [--bin 0.003]
"""
import argparse
import shutil

import h5py
import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("inp")
ap.add_argument("out")
ap.add_argument("--bin", type=float, default=0.003, help="bin size [m] (about a ball diameter)")
a = ap.parse_args()
shutil.copyfile(a.inp, a.out)
with h5py.File(a.out, "r+") as f:
    pos = f["reals/pos"][:].reshape(-1, 3)
    n = len(pos)
    ijk = np.floor((pos - pos.min(axis=0)) / a.bin).astype(np.int64)
    dims = ijk.max(axis=0) + 1
    key = (ijk[:, 2] * dims[1] + ijk[:, 1]) * dims[0] + ijk[:, 0]   # x fastest, then y, then z
    order = np.argsort(key, kind="stable")           # new index k holds old ball order[k]
    new_of_old = np.empty(n, np.int64)
    new_of_old[order] = np.arange(n)
    for name in ("dissipated", "inertia", "mass", "radius", "work_in"):
        f["reals/" + name][:] = f["reals/" + name][:][order]
    for name in ("pos", "vel", "omega"):
        f["reals/" + name][:] = f["reals/" + name][:].reshape(n, 3)[order].ravel()
    hid = f["ints/hist_id"][:].reshape(n, -1)[order]
    hxi = f["reals/hist_xi"][:].reshape(n, -1, 3)[order]
    hid = np.where(hid >= 0, new_of_old[np.clip(hid, 0, n - 1)], hid)  # negative: no partner
    f["ints/hist_id"][:] = hid.ravel()
    f["reals/hist_xi"][:] = hxi.ravel()
    print(f"{n} balls sorted into {dims.tolist()} bins of {a.bin} m")
