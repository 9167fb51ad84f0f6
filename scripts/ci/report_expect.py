"""What the HDF5 files hold where the report's browser test looks (scripts/ci/test-report.sh):
read with h5py, independently of squeal, and written as JSON for test-report.mjs.

    python report_expect.py DIR > expect.json

DIR holds scan.h5 (Fig. 9), sweep.h5 (a physical scan over three dashpots), atlas.h5 (an
atlas with maps) and trajectory.h5 (a physical run), and their .html reports.
"""

import json
import sys
from pathlib import Path

import h5py
import numpy as np


def enum_name(ds, code):
    names = {v: k for k, v in h5py.check_enum_dtype(ds.dtype).items()}
    return names[int(code)]


def nearest(values, target):
    return int(np.argmin(np.abs(np.asarray(values) - target)))


def cell(f, labels_name, m, x_target, y_target, si):
    xs = f["x0_si"][:] if si else f["x0"][:]
    vs = f["v0_si"][:] if si else f["v0"][:]
    i, j = nearest(xs, x_target), nearest(vs, y_target)
    ds = f[labels_name]
    code = ds[m, j, i] if ds.ndim == 3 else ds[j, i]
    return {"x": float(xs[i]), "y": float(vs[j]), "label": enum_name(ds, code), "si": si}


def main(d):
    d = Path(d)
    out = {}
    with h5py.File(d / "scan.h5", "r") as f:
        # A start just beside the fixed point (1, 0), then the state at rest (Fig. 9: it
        # squeals; the screenshot shows the oscillation it reaches).
        out["scan"] = {"report": str(d / "scan.html"),
                       "cells": [cell(f, "labels", 0, 1.05, 0.05, False), cell(f, "labels", 0, 0.0, 0.0, False)]}
    with h5py.File(d / "sweep.h5", "r") as f:
        lu, vu = float(f.attrs["length_unit"]), float(f.attrs["velocity_unit"])
        c = float(f["c"][2])
        out["sweep"] = {"report": str(d / "sweep.html"), "third_words": f"c = {c:g}",
                        "cells": [cell(f, "labels", 2, 0.0, 0.0, True), cell(f, "labels", 2, 1.05 * lu, 0.05 * vu, True)]}
    with h5py.File(d / "atlas.h5", "r") as f:
        nu, frac = f["nu"][:], f["basin_fraction"][:]
        k = int(np.flatnonzero(np.isfinite(frac))[0])
        out["atlas"] = {"report": str(d / "atlas.html"),
                        "point": {"x": float(nu[k]), "y": float(frac[k]), "critical": float(f["critical_nu"][0]),
                                  "map_cell": cell(f, "map_labels", k, 0.0, 0.0, False)}}
    out["trajectory"] = {"report": str(d / "trajectory.html"), "time_axis": "time (s)"}
    if (d / "big.html").exists():
        out["big"] = {"report": str(d / "big.html")}
    json.dump(out, sys.stdout, indent=1)


if __name__ == "__main__":
    main(sys.argv[1])
