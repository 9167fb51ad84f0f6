#!/usr/bin/env python3
"""Compares two atlas files (OLD NEW): every point's regime, each fold against the old
fold's stated uncertainty, each critical value against the old bracket, and how many
values of every other dataset differ (and by how much, relatively).

    python3 scripts/tools/atlas-diff.py old.h5 new.h5   (needs h5py and numpy)
"""
import sys

import h5py
import numpy as np

old, new = (h5py.File(p, "r") for p in sys.argv[1:3])
bad = 0
r0, r1 = old["regime"][()], new["regime"][()]
changed = int((r0 != r1).sum())
print(f"regime: {changed} of {r0.size} points changed")
bad += changed
f0, f1, e0 = old["fold_nu"][()], new["fold_nu"][()], old["fold_nu_err"][()]
moved = np.abs(f1 - f0)
both = np.isfinite(f0) & np.isfinite(f1)
outside = int((moved[both] > e0[both]).sum()) + int((np.isfinite(f0) != np.isfinite(f1)).sum())
print(f"fold_nu: {int((f0 != f1).sum())} of {f0.size} differ; largest move "
      f"{np.nanmax(moved / e0) if both.any() else 0:.3g} of the old uncertainty; {outside} outside it")
bad += outside
c0, c1 = old["critical_nu"][()], new["critical_nu"][()]
lo, hi = old["critical_nu_lo"][()], old["critical_nu_hi"][()]
w = hi - lo
out_c = int(((np.abs(c1 - c0) > w) & np.isfinite(c0)).sum()) + int((np.isfinite(c0) != np.isfinite(c1)).sum())
print(f"critical_nu: {int((c0 != c1).sum())} of {c0.size} differ; {out_c} moved by more than the old bracket's width")
bad += out_c
for k in sorted(old.keys()):
    if k not in new or old[k].dtype.kind not in "fiu":
        continue
    a, b = old[k][()], new[k][()]
    if a.shape != b.shape:
        print(f"{k}: shape {a.shape} -> {b.shape}")
        bad += 1
        continue
    same = (a == b) | (np.isnan(a) & np.isnan(b)) if a.dtype.kind == "f" else a == b
    n = int((~same).sum())
    if n:
        rel = np.abs(b - a) / np.maximum(np.abs(a), 1e-300)
        print(f"  {k}: {n} of {a.size} differ, largest relative change {np.nanmax(np.where(same, 0, rel)):.3g}")
print("OK" if bad == 0 else f"{bad} results moved beyond their stated uncertainty")
sys.exit(1 if bad else 0)
