#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = ["h5py", "matplotlib", "numpy"]
# ///
"""Plot a squeal basin map from its HDF5 file with matplotlib, reading the label names from
the file's HDF5 enum type (no squeal code needed). For sweeps, pick the map with --map.

Run it with uv, which reads the dependencies from the header above:
    uv run scripts/tools/plot_basins.py out/fig9.h5 -o fig9.png
or install them once and use python3:
    python3 -m pip install h5py matplotlib numpy
    python3 scripts/tools/plot_basins.py out/fig9.h5 -o fig9.png"""
import argparse
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.colors import ListedColormap
except ImportError as e:
    sys.exit(
        f"plot_basins.py needs h5py, matplotlib and numpy ({e}).\n"
        "Run it with uv, which installs them from the script's header:\n"
        "    uv run scripts/tools/plot_basins.py FILE.h5 -o FILE.png\n"
        "or install them first:\n"
        "    python3 -m pip install h5py matplotlib numpy"
    )

COLOURS = {"steady_slip": "#3b75af", "stick_slip": "#ef8636", "undecided": "#d62fd6", "not_computed": "#d9d9d9"}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("file", help="scan file written by squeal scan")
    ap.add_argument("-o", "--out", required=True, help="picture to write (.png, .pdf, ...)")
    ap.add_argument("--map", type=int, default=0, help="map index of a sweep")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        schema = f.attrs.get("schema", "")
        if isinstance(schema, bytes):
            schema = schema.decode()
        if schema != "squeal-basins/1":
            found = f"schema = {schema}" if schema else "no schema attribute"
            hint = (" (an atlas file: its basin maps are the map_* datasets; squeal render draws them)"
                    if str(schema).startswith("squeal-atlas") else "")
            raise SystemExit(f"{a.file}: not a squeal basin file ({found}; expected squeal-basins/1){hint}")
        labels = f["labels"]
        members = h5py.check_enum_dtype(labels.dtype)  # name -> value
        nmaps = labels.shape[0] if labels.ndim == 3 else 1
        if not 0 <= a.map < nmaps:
            valid = f"0..{nmaps - 1}" if nmaps > 1 else "0 (the file holds one map)"
            raise SystemExit(f"{a.file}: --map {a.map} is out of range; valid: {valid}")
        data = labels[a.map] if labels.ndim == 3 else labels[()]
        x0, v0 = f["x0"][()], f["v0"][()]
        law = f.attrs["law"]
        law = law.decode() if isinstance(law, bytes) else str(law)
        stribeck = law == "stribeck"
        keys = ("xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v") if stribeck else ("nu", "lambda", "tau", "phi")
        name = f.attrs.get("name", "")
        name = name.decode() if isinstance(name, bytes) else str(name)
        title = f"{name}: {law}" if name else law
        values = {}
        for p in keys + ("dt",):
            if p in f and f[p].ndim == 1 and labels.ndim == 3:
                values[p] = float(f[p][a.map])
            elif p in f.attrs:
                values[p] = float(f.attrs[p])
            if p in values:
                title += f", {p} = {values[p]:.4g}"
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
              extent=(x0[0] - dx, x0[-1] + dx, v0[0] - dv, v0[-1] + dv), aspect="equal", interpolation="nearest")
    if cyc is not None:
        ax.plot(np.append(cyc[0], cyc[0][0]), np.append(cyc[1], cyc[1][0]), "k-", lw=1, label="unstable limit cycle")
    # The steady-slip fixed point: x* = 1 for McMillan's laws; x* = mu(v_d) for the Stribeck
    # law (x' = 0, slip -v_d: the spring holds the friction force at that slip speed).
    if stribeck:
        v = values
        x_star = v["mu_d"] + v["mu_d"] * (v["mu_sd"] - 1) * np.exp(-v["v_d"] / v["v_0"]) + v["mu_v"] * v["v_d"] / v["v_0"]
    else:
        x_star = 1.0
    ax.plot([x_star], [0.0], "k+", ms=10, label=f"fixed point ({x_star:.3g}, 0)")
    ax.plot([0.0], [0.0], "rx", ms=8, label="state at rest (0, 0)")
    for n in names:
        ax.plot([], [], "s", color=COLOURS.get(n, "grey"), label=f"{n} ({int((data == members[n]).sum())})")
    if stribeck:
        # bSTAB's friction case is written nondimensionally already (MODEL.md, section 8).
        ax.set_xlabel("initial displacement x0 (nondimensional, bSTAB's friction case)")
        ax.set_ylabel("initial velocity x'0 (nondimensional, bSTAB's friction case)")
    else:
        # Nondimensional units (docs/model.md, "Units"): x in mu_k m g / k, x' in mu_k g / sqrt(k/m).
        ax.set_xlabel("initial displacement x0 (units of mu_k m g / k)")
        ax.set_ylabel("initial velocity x'0 (units of mu_k g sqrt(m/k))")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8)
    fig.savefig(a.out, dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    main()
