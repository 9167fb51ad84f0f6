"""First steps with squeal from Python, for a vibration engineer: a basin map, a stability
chart and bSTAB's belt-speed study of basin stability, each in a few lines.

    pip install target/wheels/squeal-*.whl matplotlib   # or: pip install ".[examples]"
    python examples/first_steps.py                      # -> examples/out/*.png

3.7 minutes on the shared 2-core development machine at load 10 (most of it the
belt-speed study: 20 x 5000 runs)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402

import squeal  # noqa: E402

out = Path(__file__).parent / "out"
out.mkdir(exist_ok=True)

# 1. A basin map: McMillan's hysteretic law at damping nu = 0.01 (paper's Table 1
#    otherwise). Every start (x0, x'0) is labelled steady slip or stick-slip ("squeal").
basins = squeal.scan(
    {
        "version": 1,
        "model": {"law": "mcmillan", "nu": 1e-2},
        "grid": {
            "x0": {"min": -3.0, "max": 5.0, "count": 160},
            "v0": {"min": -4.0, "max": 4.0, "count": 160},
        },
        "output": {"path": "basins.h5"},
    }
)
cycle = squeal.ulc(law="mcmillan", nu=1e-2)  # the basin boundary
fig, ax = plt.subplots(figsize=(6, 5))
basins["labels"].plot(ax=ax, levels=[0.5, 1.5, 2.5], colors=["tab:blue", "tab:red"],
                      add_colorbar=False)
ax.plot(cycle.x, cycle.v, "k-", lw=1.5, label="unstable limit cycle")
ax.set(title="nu = 0.01: steady slip (blue) or squeal (red)", xlabel="x0", ylabel="x'0")
ax.legend(loc="upper right")
fig.savefig(out / "basin-map.png", dpi=120)
print("steady-slip share of the map:", float(basins["basin_stability_steady_slip"][0]))

# 2. A stability chart of the Stribeck law (bSTAB's friction case): the regime over
#    damping ratio xi and belt speed v_d, with the basin fraction of steady slip of
#    starts in x in [-2, 2], x' in [0, 2] as contours.
chart = squeal.atlas(
    {
        "version": 1,
        "name": "chart",
        "model": {
            "law": "stribeck",
            "xi": {"from": 0.01, "to": 0.15, "count": 10, "spacing": "log"},
            "v_d": {"from": 0.5, "to": 3.0, "count": 10},
        },
        "disturbance": {"x": [-2.0, 2.0], "v": [0.0, 2.0]},
        "output": {"path": "chart.h5"},
    }
)
colors = {1: "tab:blue", 2: "lightsteelblue", 3: "navajowhite", 4: "tab:orange"}
fig, ax = plt.subplots(figsize=(7, 5))
regime = chart["regime"].where(chart["regime"].isin(list(colors)))
regime.plot(ax=ax, levels=[0.5, 1.5, 2.5, 3.5, 4.5], colors=list(colors.values()),
            add_colorbar=False)
cs = chart["basin_fraction"].plot.contour(ax=ax, levels=[0.25, 0.5, 0.75], colors="k")
ax.clabel(cs)
ax.set_yscale("log")
names = squeal.flags(chart["regime"])  # {1: "steady_slip_only", ...}
ax.legend(handles=[Patch(color=c, label=names[v].replace("_", " ")) for v, c in colors.items()],
          loc="upper right", fontsize=8)
ax.set_title("regime, and the basin fraction of steady slip (contours)")
fig.savefig(out / "stability-chart.png", dpi=120)

# 3. bSTAB's belt-speed study: basin stability of steady slip against v_d, 5000 random
#    starts per speed, with the binomial standard error as error bars.
v_d = np.linspace(0.8, 2.225, 20)
bs = squeal.basin_stability("stribeck", xi=0.05, v_d=v_d, mu_d=0.5, mu_sd=2.0, v_0=0.5,
                            n=5000, seed=1)
fig, ax = plt.subplots(figsize=(6, 4))
for regime in ("steady_slip", "stick_slip"):
    ax.errorbar(bs.values, bs.shares[regime], yerr=bs.errors[regime], capsize=3,
                marker="o", label=regime.replace("_", " "))
ax.set(xlabel="belt speed v_d", ylabel="basin stability", title="bSTAB friction case")
ax.legend()
fig.savefig(out / "belt-speed-study.png", dpi=120)
for v, p, e in zip(bs.values, bs.shares["steady_slip"], bs.errors["steady_slip"]):
    print(f"v_d = {v:.3f}: steady slip {p:.4f} +- {e:.4f}")
