#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = ["h5py", "matplotlib", "numpy"]
# ///
"""Plot a squeal basin map from its HDF5 file with matplotlib, reading the label names from
the file's HDF5 enum type (no squeal code needed). For sweeps, pick the map with --map."""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

COLOURS = {"steady_slip": "#3b75af", "stick_slip": "#ef8636", "undecided": "#d62fd6", "not_computed": "#d9d9d9"}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("file", help="scan file written by squeal scan")
    ap.add_argument("-o", "--out", required=True, help="picture to write (.png, .pdf, ...)")
    ap.add_argument("--map", type=int, default=0, help="map index of a sweep")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        if f.attrs.get("schema", "") != "squeal-basins/1":
            raise SystemExit(f"{a.file}: not a squeal basin file (no schema attribute)")
        labels = f["labels"]
        members = h5py.check_enum_dtype(labels.dtype)  # name -> value
        data = labels[a.map] if labels.ndim == 3 else labels[()]
        x0, v0 = f["x0"][()], f["v0"][()]
        title = f"{f.attrs['law']}"
        for p in ("nu", "lambda"):
            if p in f and f[p].ndim == 1 and labels.ndim == 3:
                title += f" {p} = {f[p][a.map]:g}"
            elif p in f.attrs:
                title += f" {p} = {f.attrs[p]:g}"
        cyc = None
        g = f.get("cycle") if labels.ndim == 2 else f.get(f"cycles/map_{a.map:04d}")
        if g is not None and "x" in g:
            cyc = (g["x"][()], g["v"][()])
    names = sorted(members, key=members.get)
    index = np.zeros(256, dtype=int)
    for k, n in enumerate(names):
        index[members[n]] = k
    cmap = ListedColormap([COLOURS.get(n, "grey") for n in names])
    fig, ax = plt.subplots(figsize=(7, 6))
    dx = (x0[-1] - x0[0]) / max(len(x0) - 1, 1) / 2
    dv = (v0[-1] - v0[0]) / max(len(v0) - 1, 1) / 2
    ax.imshow(index[data], origin="lower", cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5,
              extent=(x0[0] - dx, x0[-1] + dx, v0[0] - dv, v0[-1] + dv), aspect="auto", interpolation="nearest")
    if cyc is not None:
        ax.plot(np.append(cyc[0], cyc[0][0]), np.append(cyc[1], cyc[1][0]), "k-", lw=1, label="unstable limit cycle")
    ax.plot([1.0], [0.0], "k+", ms=10, label="fixed point")
    for n in names:
        ax.plot([], [], "s", color=COLOURS.get(n, "grey"), label=f"{n} ({int((data == members[n]).sum())})")
    ax.set_xlabel("x0")
    ax.set_ylabel("x'0")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8)
    fig.savefig(a.out, dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    main()
