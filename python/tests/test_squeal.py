"""Tests of the Python package against the command line it installs (`squeal`, the same
Rust program): scan files, bSTAB's basin stability, spec errors and interruption.

Run by scripts/ci/test-python.sh in a fresh venv with the wheel installed and no Rust."""

import json
import os
import re
import shutil
import signal
import subprocess
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import squeal

# A small McMillan map: the hysteretic law at nu = 1e-2 (the fixed point is stable there,
# so the map has both basins and the unstable cycle between them), 24 x 16 cells.
SMALL = """version = 1
name = "small"

[model]
law = "mcmillan"
nu = 1e-2

[grid]
x0 = { min = -3.0, max = 5.0, count = 24 }
v0 = { min = -4.0, max = 4.0, count = 16 }

[output]
path = "small.h5"
"""

# bSTAB's friction case 1 (scans/bstab-friction.toml at v_d = 1.5) with bSTAB's sampling:
# 5000 uniform random starts in x0 in [-2, 2], x'0 in [0, 2].
BSTAB = dict(xi=0.05, v_d=1.5, mu_d=0.5, mu_sd=2.0, v_0=0.5, mu_v=0.0)


def cli(*args, cwd):
    """The `squeal` command installed with the wheel."""
    exe = shutil.which("squeal")
    assert exe, "the wheel did not put `squeal` on PATH"
    return subprocess.run(
        [exe, *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )


def read_cli_file(path):
    """What xarray reads from a file the command line wrote, with xarray's own defaults
    except that integers stay integers (no NaN masking) and nothing is read as a time."""
    with xr.open_dataset(
        path,
        engine="h5netcdf",
        mask_and_scale=False,
        decode_times=False,
        decode_timedelta=False,
    ) as ds:
        return ds.load()


def test_scan_dataset_equals_what_xarray_reads_from_the_cli_file(tmp_path):
    spec = tmp_path / "small.toml"
    spec.write_text(SMALL)
    r = cli("scan", str(spec), "-o", str(tmp_path / "cli.h5"), "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    from_cli = read_cli_file(tmp_path / "cli.h5")
    ds = squeal.scan(spec)
    # Same data, coordinates and attributes (the spec text and provenance included).
    xr.testing.assert_identical(ds, from_cli)
    assert ds["labels"].dims == ("v0", "x0")
    assert ds["labels"].dtype == np.uint8
    assert "steady_slip" in ds["labels"].attrs["flag_meanings"].split()
    # Both regimes occur, or the comparison would be weak.
    labels = set(np.unique(ds["labels"].values))
    assert {1, 2} <= labels, labels


def test_scan_dataset_carries_the_final_state_sensitivity(tmp_path):
    spec = tmp_path / "small.toml"
    spec.write_text(SMALL)
    ds = squeal.scan(spec)
    # The basin entropy, recomputed here from the labels with numpy (Daza et al. 2016:
    # boxes of 5 x 5 cells, the natural log; the boundary boxes hold two labels or more).
    labels = ds["labels"].values
    box = int(ds["basin_entropy_box"].values[0])
    assert box == 5
    entropies = []
    for j in range(0, labels.shape[0] - box + 1, box):
        for i in range(0, labels.shape[1] - box + 1, box):
            _, counts = np.unique(labels[j : j + box, i : i + box], return_counts=True)
            p = counts / counts.sum()
            entropies.append(float(-(p * np.log(p)).sum()))
    entropies = np.array(entropies)
    assert ds["basin_entropy_boxes"].values[0] == len(entropies)
    assert ds["basin_entropy"].values[0] == pytest.approx(entropies.mean(), rel=1e-12)
    boundary = entropies[entropies > 0]
    assert len(boundary) > 0, "the small map has both basins"
    assert ds["boundary_basin_entropy"].values[0] == pytest.approx(boundary.mean(), rel=1e-12)
    meaning = squeal.flags(ds["log2_test"])[int(ds["log2_test"].values[0])]
    assert meaning == ("fractal" if boundary.mean() > np.log(2) else "inconclusive")
    # The runs: every figure with its units and meaning, the changed starts over the sizes.
    for name in ("uncertainty_exponent", "step_sensitivity", "uncertainty_samples"):
        assert ds[name].attrs["units"] == "1" and ds[name].attrs["long_name"], name
    n = ds["uncertainty_samples"].values[0]
    assert n == 64  # the default for 384 cells: one per 32 cells, at least 64
    changed = ds["uncertainty_changed"]
    assert changed.dims == ("map", "uncertainty_eps")
    assert (changed.values <= n).all()
    assert 0 <= ds["step_sensitivity"].values[0] <= 1
    assert ds["sensitivity_runs"].values[0] == n * 10


def test_dict_spec_gives_the_same_map_as_the_file(tmp_path):
    spec = {
        "version": 1,
        "name": "small",
        "model": {"law": "mcmillan", "nu": 1e-2},
        "grid": {
            "x0": {"min": -3.0, "max": 5.0, "count": 24},
            "v0": {"min": -4.0, "max": 4.0, "count": 16},
        },
        "output": {"path": "small.h5"},
    }
    (tmp_path / "small.toml").write_text(SMALL)
    a = squeal.scan(spec, tmp_path / "kept.h5")
    b = squeal.scan(tmp_path / "small.toml")
    assert (tmp_path / "kept.h5").exists()
    # The spec text differs (generated from the dict); every variable and coordinate agrees.
    xr.testing.assert_equal(a, b)
    assert squeal.open(tmp_path / "kept.h5").attrs["name"] == "small"


def test_bstab_case1_basin_stability_equals_the_cli(tmp_path):
    bs = squeal.basin_stability("stribeck", n=5000, seed=1, **BSTAB)
    model = "\n".join(f"{k} = {v!r}" for k, v in BSTAB.items())
    (tmp_path / "case1.toml").write_text(
        f"""version = 1
[model]
law = "stribeck"
{model}
[sample]
kind = "random"
n = 5000
seed = 1
region = {{ x0 = [-2.0, 2.0], v0 = [0.0, 2.0] }}
[output]
path = "case1.h5"
"""
    )
    r = cli("scan", "case1.toml", "--json", "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)["maps"][0]["basin_stability"]
    assert report["n"] == bs.n == 5000
    for regime in squeal.REGIMES:
        assert bs.shares[regime] == report[regime]["p"], regime
        assert bs.errors[regime] == report[regime]["se"], regime
    # bSTAB's published case 1 (tests/data/bstab_friction_published.json): steady slip
    # (FP) 0.304 +- 0.0065 of 5000 starts. Different samples and classifiers: agreement
    # within 4 combined standard errors (4 * sqrt(2) * 0.0065 = 0.037).
    assert abs(bs.shares["steady_slip"] - 0.304) < 0.037, bs.shares


def test_belt_speed_sweep_gives_one_share_per_speed():
    bs = squeal.basin_stability(
        "stribeck", n=200, seed=3, **{**BSTAB, "v_d": [1.0, 1.5, 2.0]}
    )
    assert bs.parameter == "v_d"
    np.testing.assert_allclose(bs.values, [1.0, 1.5, 2.0])
    total = sum(bs.shares[r] for r in squeal.REGIMES)
    np.testing.assert_allclose(total, 1.0, rtol=1e-12)


def test_a_sweep_of_two_keys_gives_one_share_per_pair():
    # One map per point of the product, the last key fastest: each map's shares are those
    # of its pair swept alone (the same seeded samples, the same classifier).
    pairs = dict(xi=[0.05, 0.1], v_d=[1.0, 2.0])
    bs = squeal.basin_stability("stribeck", n=100, seed=3, **{**BSTAB, **pairs})
    assert bs.parameter == "map"
    np.testing.assert_allclose(bs.dataset["xi"].values, [0.05, 0.05, 0.1, 0.1])
    np.testing.assert_allclose(bs.dataset["v_d"].values, [1.0, 2.0, 1.0, 2.0])
    one = squeal.basin_stability("stribeck", n=100, seed=3, **{**BSTAB, "xi": 0.1, "v_d": 1.0})
    for r in squeal.REGIMES:
        assert bs.shares[r][2] == one.shares[r], r
    # The keys are coordinates over map: docs/python.md's unstack gives the grid of maps.
    grid = bs.dataset["labels"].set_index(map=["xi", "v_d"]).unstack("map")
    assert grid.sizes["xi"] == 2 and grid.sizes["v_d"] == 2


def test_spec_error_raises_value_error_with_the_cli_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(SMALL.replace("count = 24", "count = 0"))
    r = cli("scan", str(bad), "--quiet", cwd=tmp_path)
    assert r.returncode == 2
    with pytest.raises(ValueError) as e:
        squeal.scan(bad)
    assert r.stderr.strip() == f"error: {e.value}"
    assert "x0" in str(e.value)
    with pytest.raises(ValueError, match="nu"):
        squeal.basin_stability("mcmillan", n=10, nu=-1.0)


# README's brake oscillator under Coulomb friction in SI units: m, k, c, v_belt, mu_k alone
# (Coulomb's force has no static peak and no surface time, so no mu_s and no tau), on a
# 3 x 2 grid in m and m/s.
COULOMB_SI = {
    "version": 1,
    "model": {"law": "coulomb"},
    "physical": {"m": 2.0, "k": 5.0e4, "c": 10.0, "v_belt": 0.05, "mu_k": 0.35},
    "grid": {
        "x0": {"min": -1e-4, "max": 2e-4, "count": 3},
        "v0": {"min": -0.01, "max": 0.01, "count": 2},
    },
    "output": {"path": "coulomb.h5"},
}


def test_a_coulomb_system_in_si_units_takes_no_surfaces():
    # Before, mu_s and tau were required for Coulomb, then ignored (and stored as
    # physical_mu_s, physical_tau); now the file has neither and either one is refused.
    ds = squeal.scan(COULOMB_SI)
    assert ds.attrs["physical_mu_k"] == 0.35
    assert "physical_mu_s" not in ds.attrs and "physical_tau" not in ds.attrs
    for key, value in [("mu_s", 0.45), ("tau", 1e-3)]:
        bad = {**COULOMB_SI, "physical": {**COULOMB_SI["physical"], key: value}}
        with pytest.raises(ValueError, match=rf'`physical\.{key}` = given: .*"coulomb"'):
            squeal.scan(bad)


# Slow on purpose: every cell runs to t_max = 400 (no early stop), in blocks of 2 rows, so
# the signal lands mid-run. 64 blocks: with 16, a run of `.ci/run` on 2026-12-02 saw the
# scan end before the signal stopped it ("DID NOT RAISE KeyboardInterrupt"), and with 32 a
# run at load 5-10 on 2026-12-07 did too (the signal lands after the journal first grows).
SLOW = """version = 1
[model]
law = "mcmillan"
nu = 1e-2
[grid]
x0 = { min = -3.0, max = 5.0, count = 16 }
v0 = { min = -4.0, max = 4.0, count = 128 }
block_rows = 2
[classifier]
early_stop = "none"
t_max = 400.0
[output]
path = "slow.h5"
"""


def sigint_after_first_block(journal, sizes):
    """Sends SIGINT to this process once the journal has grown past its first size (the
    header: a block was stored), noting the sizes seen."""
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        if journal.exists():
            sizes.append(journal.stat().st_size)
            if sizes[-1] > sizes[0]:
                break
        time.sleep(0.01)
    os.kill(os.getpid(), signal.SIGINT)


def test_ctrl_c_raises_keyboard_interrupt_and_leaves_a_resumable_journal(tmp_path):
    spec = tmp_path / "slow.toml"
    spec.write_text(SLOW)
    out = tmp_path / "slow.h5"
    journal = Path(f"{out}.journal")
    sizes = []
    sender = threading.Thread(target=sigint_after_first_block, args=(journal, sizes))
    sender.start()
    with pytest.raises(KeyboardInterrupt):
        squeal.scan(spec, out)
    sender.join()
    assert journal.exists() and not out.exists()
    assert journal.stat().st_size > sizes[0]  # blocks are stored
    with pytest.raises(ValueError, match="resume"):
        squeal.scan(spec, out)  # the CLI's refusal: an interrupted scan is there
    resumed = squeal.scan(spec, out, resume=True)
    assert not journal.exists()
    assert (resumed["labels"].values != 255).all()
    assert resumed["blocks_done"].values.all()
    # The store's promise: a resumed run writes the file an uninterrupted one writes.
    xr.testing.assert_identical(resumed, squeal.scan(spec))


def test_ulc_and_critical_return_dataclasses_with_the_cli_values(tmp_path):
    c = squeal.ulc(law="mcmillan", nu=1e-2)
    assert c.multiplier > 1  # unstable
    assert c.x.shape == c.v.shape and c.x.size > 10
    r = cli("ulc", "--nu", "1e-2", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert c.r_section == json.loads(r.stdout)["r_section"]
    k = squeal.critical(law="mcmillan", x0=0.0, v0=0.0)
    assert k.bracket[0] <= k.value <= k.bracket[1]
    r = cli("critical", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    from_cli = json.loads(r.stdout)
    assert k.value == from_cli["nu"]
    # The step sensitivity of the confirming runs: the same figures under the same names
    # (one start at each end of the bracket, at dt and at dt/2).
    for name in ("step_sensitivity", "step_sensitivity_se", "step_sensitivity_changed",
                 "step_sensitivity_compared"):
        assert getattr(k, name) == from_cli[name], name
    assert k.step_sensitivity_compared == 2
    # The Stribeck law's fold in the belt speed (squeal critical --law stribeck --in v_d
    # --fold), as the command line finds it.
    f = squeal.critical(law="stribeck", parameter="v_d", fold=True)
    r = cli("critical", "--law", "stribeck", "--in", "v_d", "--fold", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert f.value == json.loads(r.stdout)["v_d"]
    with pytest.raises(ValueError, match="raise it"):
        squeal.critical(law="stribeck", parameter="v_d", fold=True, bracket=(0.5, 0.6))


@pytest.mark.parametrize(
    "call, keyword",
    [
        # The wrong answers found on 48d225a, where the command line refuses the flag:
        # critical(rtol=nan) answered 0.00707 after 2 evaluations (the CLI's is 0.00302),
        # ulc(r_max=nan/-1/1e300) reported no cycle "up to r = NaN" (it is at r = 2.09),
        # ulc(rtol=1), critical(rtol=-1) (200 bisection steps), critical(x0=1e300) and the
        # fold with rtol=5 ran.
        (lambda: squeal.critical(law="mcmillan", rtol=float("nan")), "rtol"),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, r_max=float("nan")), "r_max"),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, r_max=-1.0), "r_max"),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, r_max=1e300), "r_max"),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, rtol=1.0), "rtol"),
        (lambda: squeal.critical(law="mcmillan", rtol=-1.0), "rtol"),
        (lambda: squeal.critical(law="mcmillan", x0=1e300), "x0"),
        (lambda: squeal.critical(law="mcmillan", fold=True, rtol=5.0), "rtol"),
    ],
)
def test_keywords_the_command_line_refuses_are_refused_by_name(call, keyword):
    with pytest.raises(ValueError) as e:
        call()
    msg = str(e.value)
    # Named as the Python keyword, not as the command line's flag.
    assert re.search(rf"\b{keyword}\b", msg) and "--" not in msg, msg


def test_trajectory_is_a_dataset_over_time_with_the_cli_verdict(tmp_path):
    ds = squeal.trajectory(law="mcmillan", nu=1e-2, x0=0.0, v0=0.0, t_end=200.0, every=10)
    assert ds["x"].dims == ("t",)
    # dt = 0.005 (the default): 200 / 0.005 = 40000 steps, every 10th kept, and t = 0.
    assert ds.sizes["t"] == 4001
    r = cli(
        "trajectory", "--nu", "1e-2", "--t-end", "200", "--json", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    verdict = json.loads(r.stdout)["classification"]
    assert ds.attrs["regime"] == verdict["regime"]
    assert ds.attrs["t_decision"] == verdict["t_decision"]
    # t_squeal as the CLI states it (JSON has no infinity, so by kind).
    sq = verdict["squeal"]
    fixed = {"never": 0.0, "lasting": float("inf"), "unknown": -1.0}
    assert ds.attrs["t_squeal"] == fixed.get(sq["kind"], sq.get("t_squeal"))


def test_trajectory_refuses_what_the_cli_refuses():
    # A start beyond the classifier's escape radius (1e6) was labelled by the start rule
    # without a run, and t_end had no bound: 1e15 / dt 0.005 = 2e17 steps (the bound is 1e10).
    with pytest.raises(ValueError, match=r"`x0` = 1e300"):
        squeal.trajectory(law="mcmillan", nu=1e-3, x0=1e300, v0=0.0, t_end=10.0)
    with pytest.raises(ValueError, match=r"2\.000e17 steps, at most 1e10"):
        squeal.trajectory(law="mcmillan", nu=1e-3, x0=0.0, v0=0.0, t_end=1e15)


def test_atlas_dataset_equals_what_xarray_reads_from_the_cli_file(tmp_path):
    spec = tmp_path / "atlas.toml"
    spec.write_text(
        """version = 1
name = "small-atlas"
[model]
law = "stribeck"
v_d = [1.0, 1.5, 2.0]
[disturbance]
x = [-2.0, 2.0]
v = [0.0, 2.0]
[output]
path = "atlas.h5"
"""
    )
    r = cli("atlas", str(spec), "-o", str(tmp_path / "cli.h5"), "--quiet", "--no-render", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    ds = squeal.atlas(spec)
    xr.testing.assert_identical(ds, read_cli_file(tmp_path / "cli.h5"))
    assert ds["basin_fraction"].dims == ("v_d",)


def test_the_gil_is_released_while_computing(tmp_path):
    # The whole of SLOW (64 blocks, every cell run to settlement): seconds of computing in
    # the main thread. With 4 rows it took under 0.5 s on an idle machine once the certified
    # early decisions (MODEL.md section 9) came, too quick to tell.
    spec = tmp_path / "gil.toml"
    spec.write_text(SLOW)
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.005)

    t = threading.Thread(target=tick)
    t.start()
    t0 = time.monotonic()
    try:
        squeal.scan(spec)
        t1 = time.monotonic()
    finally:
        done.set()
        t.join()
    during = [x for x in ticks if t0 < x < t1]
    # A thread running beside the scan ticks about every 5 ms; with the GIL held by the
    # scan it could not tick at all until the scan returned. A quarter of the ideal count
    # leaves room for a loaded machine.
    assert t1 - t0 > 0.5, "the scan was too quick to tell"
    assert len(during) > 0.25 * (t1 - t0) / 0.005, (len(during), t1 - t0)


def test_the_namespace_is_the_api():
    # dir(squeal) listed os, sys, json, Any, tempfile, ... beside the API.
    public = {name for name in dir(squeal) if not name.startswith("_")}
    assert public == set(squeal.__all__)
    assert all(hasattr(squeal, name) for name in squeal.__all__)
    assert "__version__" in dir(squeal)


# README's disc-brake pad (section 4) in SI units: 0.8 kg on a 200 kN/m mount, 20 N s/m, disc at
# 0.3 m/s, mu_k 0.38, mu_s 0.48, surface time 0.5 ms, clamped with 1.5 kN.
PAD = dict(m=0.8, k=2e5, c=20.0, v_belt=0.3, mu_k=0.38, mu_s=0.48, tau_s=5e-4, normal_force=1500.0)


def test_the_helpers_take_the_physical_system():
    # Before: "TOML parse error at line 4 [model] unknown field `m`". Its nondimensional
    # system (crates/core/MODEL.md, "Units"): nu = c / (2 sqrt(m k)) = 0.025, lambda =
    # v_B sqrt(m k) / (mu_k N) = 120 / 570, tau' = tau omega_0 / mu_k = 0.25 / 0.38,
    # phi = arcsin(0.38 / 0.48); a start 1 mm out is 1e-3 / (mu_k N / k) = 0.3509 units.
    ds = squeal.trajectory(law="mcmillan", x0=1e-3, t_end=20.0, every=10, **PAD)
    want = {
        "nu": 0.025,
        "lambda": 120.0 / 570.0,
        "tau": 0.25 / 0.38,
        "phi": float(np.arcsin(0.38 / 0.48)),
        "x0": 1e-3 / 2.85e-3,
    }
    for key, v in want.items():
        assert ds.attrs[key] == pytest.approx(v, rel=1e-13), key
    # The g-hack g = N / m = 1875 m/s^2 (the only way to state the clamp before): the
    # same run, bit for bit.
    hack = {**{k: v for k, v in PAD.items() if k != "normal_force"}, "g": 1875.0}
    h = squeal.trajectory(law="mcmillan", x0=1e-3, t_end=20.0, every=10, **hack)
    np.testing.assert_array_equal(ds["x"].values, h["x"].values)
    # The Dataset names the system: the normal force in newtons among its attributes.
    assert ds.attrs["physical_normal_force"] == 1500.0
    assert ds.attrs["physical_normal_force_units"] == "N"
    # The same as a [physical] table (its surface time is `tau`, in s).
    table = {**{k: v for k, v in PAD.items() if k != "tau_s"}, "tau": 5e-4}
    t = squeal.trajectory(law="mcmillan", x0=1e-3, t_end=20.0, every=10, physical=table)
    np.testing.assert_array_equal(t["x"].values, ds["x"].values)


def test_physical_datasets_carry_si_coordinates(tmp_path):
    # Before, a physical run's Dataset was in the model's units only
    # (x0, v0, nu, t). Now the SI coordinates come beside them, as coordinates: the
    # trajectory's time in s (its x and x' in m and m/s as variables), a scan's grid in m
    # and m/s and its swept dashpot in N s/m. The clamped pad's length unit is
    # mu_k N / k = 2.85 mm, its time unit sqrt(m / k) = 2 ms (MODEL.md, "Units").
    ds = squeal.trajectory(law="mcmillan", x0=1e-3, t_end=20.0, every=10, **PAD)
    assert "t_si" in ds.coords and ds["t_si"].attrs["units"] == "s"
    np.testing.assert_allclose(ds["t_si"].values, ds["t"].values * 2e-3, rtol=1e-15)
    assert ds["x_si"].attrs["units"] == "m" and ds["v_si"].attrs["units"] == "m/s"
    assert ds["x_si"].values[0] == pytest.approx(1e-3, rel=1e-15)
    spec = {
        "version": 1,
        "name": "pad",
        "model": {"law": "mcmillan"},
        "physical": {**{k: v for k, v in PAD.items() if k != "tau_s"}, "tau": 5e-4,
                     "c": [20.0, 100.0]},
        "grid": {
            "x0": {"min": -2e-3, "max": 6e-3, "count": 2},
            "v0": {"min": -0.5, "max": 0.5, "count": 2},
        },
        "output": {"path": "pad.h5"},
    }
    scan = squeal.scan(spec, tmp_path / "pad.h5")
    for name, units, want in [
        ("x0_si", "m", [-2e-3, 6e-3]),
        ("v0_si", "m/s", [-0.5, 0.5]),
        ("c", "N s/m", [20.0, 100.0]),
    ]:
        assert name in scan.coords, name
        assert scan[name].attrs["units"] == units, name
        np.testing.assert_allclose(scan[name].values, want, rtol=1e-12)
    assert scan["labels"].dims == ("nu", "v0", "x0")
    assert set(scan["labels"].coords) >= {"x0_si", "v0_si", "c"}
    # basin_stability over a physical c sweep answers in c, as swept (before: nu).
    pad = {k: v for k, v in PAD.items() if k != "c"}
    bs = squeal.basin_stability(
        "mcmillan", c=[20.0, 100.0], n=4, region=((-2e-3, 6e-3), (-0.5, 0.5)), **pad
    )
    assert bs.parameter == "c"
    np.testing.assert_allclose(bs.values, [20.0, 100.0], rtol=1e-12)
    assert bs.dataset["x0_si"].attrs["units"] == "m"


def test_a_physical_sweep_of_the_surfaces_answers_in_its_keys():
    # Before, a scan under [physical] refused a list of any key but c and v_belt. The maps
    # are indexed by the model's phi and tau (MODEL.md: phi = arcsin(mu_k / mu_s), tau' =
    # tau omega_0 / mu_k), with mu_s and the surface time in s (`tau_si`) as given.
    pad = {k: v for k, v in PAD.items() if k not in ("mu_s", "tau_s")}
    region = ((-2e-3, 6e-3), (-0.5, 0.5))
    bs = squeal.basin_stability("mcmillan", mu_s=[0.45, 0.5], tau_s=5e-4, n=4, region=region, **pad)
    assert bs.parameter == "mu_s"
    np.testing.assert_array_equal(bs.values, [0.45, 0.5])
    np.testing.assert_allclose(bs.dataset["phi"].values, np.arcsin(0.38 / np.array([0.45, 0.5])),
                               rtol=1e-14)
    bs = squeal.basin_stability("mcmillan", mu_s=0.48, tau_s=[5e-4, 1e-3], n=4, region=region, **pad)
    assert bs.parameter == "tau_si" and bs.dataset["tau_si"].attrs["units"] == "s"
    np.testing.assert_array_equal(bs.values, [5e-4, 1e-3])
    # tau' = tau omega_0 / mu_k with omega_0 = sqrt(k / m) = 500 rad/s.
    np.testing.assert_allclose(bs.dataset["tau"].values, np.array([5e-4, 1e-3]) * 500 / 0.38,
                               rtol=1e-14)


def test_physical_errors_name_the_python_keyword():
    with pytest.raises(ValueError, match=r"`normal_force=` = 0"):
        squeal.ulc(law="mcmillan", **{**PAD, "normal_force": 0.0})
    with pytest.raises(ValueError, match=r"`tau_s=` = -1"):
        squeal.critical(law="mcmillan", **{**PAD, "tau_s": -1.0})
    with pytest.raises(ValueError, match=r"`normal_force=` = given with g"):
        squeal.trajectory(law="mcmillan", t_end=1.0, g=9.81, **PAD)
    table = {**{k: v for k, v in PAD.items() if k != "tau_s"}, "tau": 5e-4, "m": -1.0}
    with pytest.raises(ValueError, match=r"`physical\['m'\]` = -1"):
        squeal.ulc(law="mcmillan", physical=table)
    with pytest.raises(ValueError, match="nu= is a nondimensional parameter"):
        squeal.ulc(law="mcmillan", nu=0.01, **PAD)
    with pytest.raises(ValueError, match="region=: give the region in m and m/s"):
        squeal.basin_stability("mcmillan", n=10, **PAD)


def test_critical_of_the_clamped_brake_comes_from_runs_as_on_the_command_line(tmp_path):
    # The brake lies outside the region the unstable cycle's shortcut was checked in
    # (lambda 0.21 < 0.5): Python passes the command line's gate and gets the runs' answer,
    # the same number (crates/core/MODEL.md section 13). Before, 13.77 N s/m from the cycle.
    k = squeal.critical(law="mcmillan", horizon=3000.0, rtol=1e-3, **PAD)
    assert k.by == "runs" and "not checked" in k.why
    c = k.value * 800.0  # nu = c / (2 sqrt(m k)), 2 sqrt(0.8 * 2e5) = 800
    assert 140.0 < c < 175.0, c
    args = ["critical", "--horizon", "3000", "--rtol", "1e-3", "--json"]
    for key, v in PAD.items():
        args += ["--" + key.replace("_", "-"), repr(v)]
    r = cli(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert k.value == json.loads(r.stdout)["nu"]


def test_the_readmes_three_lines_give_the_pads_squeal_in_si(capsys):
    # The clamped pad's squeal frequency and amplitude from Python in three lines,
    # as README's section 5 shows them (run here as written). The command line's run of the
    # same pad (README section 4, `squeal trajectory ... --c 20 --t-end 3000`) ends on the
    # lasting oscillation at 279 Hz, x in 1.59..1.97 mm, x' in -0.43..+0.42 m/s. Before, the
    # file had no lasting_* attributes.
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    three = [b for b in blocks if b.startswith("pad = dict(")]
    assert len(three) == 1 and len(three[0].strip().splitlines()) == 3, three
    exec(three[0], {"squeal": squeal})
    hz, x_max, v_max = (float(w) for w in capsys.readouterr().out.split())
    assert 270.0 < hz < 290.0
    assert 1.9e-3 < x_max < 2.05e-3
    assert 0.38 < v_max < 0.46


def test_an_existing_out_is_refused_without_force_in_pythons_words(tmp_path):
    # squeal.trajectory(out=...) once overwrote any file there, a finished scan's
    # included, where `squeal trajectory --out` refuses without --force. And the store's
    # refusals named the command line's flags (`use --force`) to Python users.
    precious = tmp_path / "precious.h5"
    precious.write_bytes(b"a finished scan")
    with pytest.raises(ValueError, match=r"force=True") as e:
        squeal.trajectory(law="mcmillan", nu=1e-3, t_end=1.0, out=precious)
    assert "--force" not in str(e.value)
    assert precious.read_bytes() == b"a finished scan"
    ds = squeal.trajectory(law="mcmillan", nu=1e-3, t_end=1.0, out=precious, force=True, every=1)
    assert ds["t"].values[-1] == pytest.approx(1.0)
    spec = tmp_path / "s.toml"
    spec.write_text(
        'version = 1\n[model]\nlaw = "mcmillan"\nnu = 1e-3\n[grid]\n'
        "x0 = { min = -1.0, max = 1.0, count = 2 }\nv0 = { min = -1.0, max = 1.0, count = 2 }\n"
        '[output]\npath = "s.h5"\n'
    )
    with pytest.raises(ValueError, match=r"force=True") as e:
        squeal.scan(spec, out=precious)
    assert "--force" not in str(e.value)


def test_a_finished_scan_is_up_to_date_with_and_without_resume(tmp_path, capsys):
    # scan(out=<finished file>) and resume=True on it once raised "use --force", where
    # the command line says "up to date" and exits 0, so the documented "same call with
    # resume=True" failed when Ctrl-C landed after the run had finished. A file of another
    # spec is still refused, naming force=True.
    spec = {
        "version": 1,
        "model": {"law": "mcmillan", "nu": 1e-2},
        "grid": {"x0": {"min": -1.0, "max": 1.0, "count": 2},
                 "v0": {"min": -1.0, "max": 1.0, "count": 2}},
        "output": {"path": "u.h5"},
    }
    out = tmp_path / "u.h5"
    first = squeal.scan(spec, out)
    stamp = out.stat().st_mtime_ns
    for resume in (False, True):
        again = squeal.scan(spec, out, resume=resume)
        assert "is up to date" in capsys.readouterr().err
        assert (again["labels"].values == first["labels"].values).all()
        assert out.stat().st_mtime_ns == stamp
    other = {**spec, "model": {"law": "mcmillan", "nu": 2e-2}}
    with pytest.raises(ValueError, match=r"different spec .*force=True"):
        squeal.scan(other, out)
    assert out.stat().st_mtime_ns == stamp


def test_a_month_long_scan_is_refused_without_allow_long(tmp_path):
    # squeal.scan once started a run the command line refuses before anything runs
    # ("64000000 cells ... would take roughly 1852 days on 2 thread(s) at the documented
    # rate: ... or pass --allow-long", `squeal scan` of this spec). Python refuses it the
    # same way, in its own words, and touches no file.
    spec = {
        "version": 1,
        "model": {"law": "mcmillan", "nu": 1e-3},
        "grid": {"x0": {"min": -1.0, "max": 1.0, "count": 8000},
                 "v0": {"min": -1.0, "max": 1.0, "count": 8000}},
        "classifier": {"t_max": 100000.0, "early_stop": "none"},
        "output": {"path": "long.h5"},
    }
    with pytest.raises(ValueError, match=r"roughly \d+ days .*allow_long=True") as e:
        squeal.scan(spec, tmp_path / "long.h5")
    assert "--allow-long" not in str(e.value)
    assert list(tmp_path.iterdir()) == []


def test_the_tabulated_law_takes_a_table_or_a_csv(tmp_path):
    # bSTAB's Stribeck law (mu_d = 0.5, mu_sd = 2, v_0 = 0.5) tabulated at 2001 rows to
    # s = 20: the same verdict as the formula from a start that squeals and one that does
    # not (bSTAB's case 1, v_d = 1.5, is bistable), and the run's Dataset holds the table.
    s = np.linspace(0.0, 20.0, 2001)
    rows = list(zip(s, 0.5 + 0.5 * np.exp(-s / 0.5)))
    for x0, v0, regime in [(-1.0, 0.5, "stick_slip"), (0.5, 0.1, "steady_slip")]:
        table = squeal.trajectory(law="table", friction_table=rows, x0=x0, v0=v0, t_end=30.0)
        formula = squeal.trajectory(law="stribeck", x0=x0, v0=v0, t_end=30.0)
        assert table.attrs["regime"] == formula.attrs["regime"] == regime
    assert table["friction_table_mu"].dims == ("table_row",)
    assert table["friction_table_mu"].values[0] == 1.0
    assert len(table["friction_table_slip_speed"]) == 2001
    # A CSV file, as the command line's --friction-csv reads it.
    csv = tmp_path / "pad.csv"
    csv.write_text("slip_speed,mu\n0,0.6\n0.5,0.45\n2,0.4\n")
    cycle = squeal.ulc(law="table", friction_csv=str(csv), v_d=0.5)
    r = cli(
        "ulc", "--law", "table", "--friction-csv", str(csv), "--v-d", "0.5", "--json", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    assert cycle.r_section == json.loads(r.stdout)["r_section"]
    # Hostile tables are refused naming the keyword and the row.
    with pytest.raises(ValueError, match=r"`friction_table=` = given: friction table row 3"):
        squeal.ulc(law="table", friction_table=[(0.0, 0.5), (1.0, 0.4), (0.5, 0.3)])
    with pytest.raises(ValueError, match=r"`friction_table=` = nan"):
        squeal.ulc(law="table", friction_table=[(0.0, 0.5), (1.0, float("nan"))])
    with pytest.raises(ValueError, match=r"`friction_csv=` = .*nowhere\.csv"):
        squeal.critical(law="table", parameter="xi", friction_csv=str(tmp_path / "nowhere.csv"))
    with pytest.raises(ValueError, match=r"`friction_table=` = given with law = \"stribeck\""):
        squeal.basin_stability("stribeck", n=10, friction_table=rows)


def test_the_readmes_three_lines_give_the_table_pads_squeal_in_si(capsys, monkeypatch):
    # The pad clamped with 1500 N on a measured curve (scans/data/pad-mu.csv, slip
    # speed in m/s), its squeal in Hz, m and m/s from Python in three lines, as README's
    # section 5 shows them (run here as written, from the repository's root where its path
    # points). Before, law="table" with the physical keywords was refused ("the physical
    # units are McMillan's scaling"). tests/table_law.rs measures the same run on the
    # command line: 66.36 Hz, x up to 4.01 mm, x' up to the disc's 0.3 m/s (it sticks).
    root = Path(__file__).resolve().parents[2]
    monkeypatch.chdir(root)
    readme = (root / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    three = [b for b in blocks if b.startswith("brake = dict(")]
    assert len(three) == 1 and len(three[0].strip().splitlines()) == 3, three
    exec(three[0], {"squeal": squeal})
    hz, x_max, v_max = (float(w) for w in capsys.readouterr().out.split())
    assert hz == pytest.approx(66.36, abs=0.01)
    assert x_max == pytest.approx(4.01e-3, abs=1e-5)
    assert v_max == pytest.approx(0.3, abs=1e-9)
    # The same system given in the model's units (crates/core/MODEL.md section 8: xi = c /
    # (2 sqrt(m k)) = 20 / 800, v_d = v_B sqrt(m k) / N = 0.08, the curve's speeds over
    # N / sqrt(m k) = 3.75 m/s): the same lasting oscillation, its omega times omega_0 / (2
    # pi) = 500 / (2 pi) the frequency in Hz.
    rows = np.loadtxt(root / "scans/data/pad-mu.csv", delimiter=",", skiprows=4)
    nd = squeal.trajectory(
        law="table",
        friction_table=[(s / 3.75, mu) for s, mu in rows],
        xi=0.025,
        v_d=0.08,
        t_end=3000,
        every=100,
    )
    assert nd.attrs["lasting_omega"] * 500 / (2 * np.pi) == pytest.approx(hz, rel=1e-6)
    # A curve in m/s with a negative speed is refused naming the keyword.
    pad = dict(m=0.8, k=2e5, c=20.0, v_belt=0.3, normal_force=1500.0)
    with pytest.raises(ValueError, match=r"`friction_table=`.*row 2"):
        squeal.trajectory(law="table", friction_table=[(0.0, 0.48), (-0.1, 0.4)], **pad)
    with pytest.raises(ValueError, match=r"`mu_k=` = given"):
        squeal.trajectory(law="table", friction_csv="scans/data/pad-mu.csv", mu_k=0.4, **pad)


def test_report_writes_the_same_page_as_the_cli_and_refuses_what_it_refuses(tmp_path):
    # One small scan, its page from Python and from the command line: the same bytes (the
    # same library writes both), beside the file by default, refused over an existing page.
    (tmp_path / "small.toml").write_text(SMALL)
    r = cli("scan", "small.toml", "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    page = squeal.report(tmp_path / "small.h5")
    assert page == tmp_path / "small.html"
    # The page names the file as it was given: the same path from both doors.
    r = cli("report", str(tmp_path / "small.h5"), "-o", "cli.html", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert page.read_bytes() == (tmp_path / "cli.html").read_bytes()
    text = page.read_text()
    assert '<script type="application/json" id="squeal-data">' in text
    with pytest.raises(ValueError, match="force=True"):
        squeal.report(tmp_path / "small.h5")
    assert squeal.report(str(tmp_path / "small.h5"), out=tmp_path / "again.html", force=True).exists()
    (tmp_path / "foreign.h5").write_bytes(b"not hdf5 at all")
    with pytest.raises(ValueError, match="not an HDF5 file"):
        squeal.report(tmp_path / "foreign.h5", out=tmp_path / "f.html")
    with pytest.raises(TypeError, match="force"):
        squeal.report(tmp_path / "small.h5", force="yes")


def test_trajectory_without_every_keeps_what_the_cli_keeps(tmp_path):
    # Without every=, both doors keep every 12th step of dt = 0.005 (at least 100 samples per
    # natural period 2 pi: floor(2 pi / (100 * 0.005)) = 12); every=1 kept every step.
    ds = squeal.trajectory(law="mcmillan", nu=1e-2, t_end=200.0)
    r = cli("trajectory", "--nu", "1e-2", "--t-end", "200", "--out", "run.h5", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    ref = read_cli_file(tmp_path / "run.h5")
    assert int(ds.attrs["every"]) == int(ref.attrs["every"]) == 12
    assert ds.sizes["t"] == ref.sizes["t"]
    assert "default" in ds.attrs["sampling"]


def test_a_curve_in_percent_or_mm_per_s_is_warned_of_before_any_run(tmp_path):
    # The brake of README section 4 (0.8 kg, 200 kN/m, c = 60 N s/m, 0.3 m/s, 1.5 kN) on
    # scans/data/pad-mu.csv written in percent (mu = 48 at rest) or in mm/s (speeds to
    # 2000): each is said as a UserWarning naming the keyword, as the command line says it
    # on stderr; the curve as shipped is said nothing. A belt speed the step cannot resolve
    # (a clamp of 1e308 N: lambda 4.5e-307) is refused naming its keyword. Before, all ran
    # silently.
    root = Path(__file__).resolve().parents[2]
    rows = np.loadtxt(root / "scans/data/pad-mu.csv", delimiter=",", skiprows=4)
    pad = dict(m=0.8, k=2e5, c=60.0, v_belt=0.3, normal_force=1500.0)
    for name, scale, words in [
        ("pct.csv", (1.0, 100.0), r"`friction_csv=`: mu reaches 48 "),
        ("mm.csv", (1000.0, 1.0), r"`friction_csv=`: its slip speeds run to 2000 m/s"),
    ]:
        csv = tmp_path / name
        text = [f"{float(s) * scale[0]!r},{float(mu) * scale[1]!r}\n" for s, mu in rows]
        csv.write_text("".join(text))
        with pytest.warns(UserWarning, match=words):
            squeal.trajectory(law="table", friction_csv=str(csv), t_end=1.0, **pad)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        shipped = str(root / "scans/data/pad-mu.csv")
        squeal.trajectory(law="table", friction_csv=shipped, t_end=1.0, **pad)
    brake = dict(m=2.0, k=5e4, c=10.0, v_belt=0.05, mu_k=0.35, mu_s=0.45, tau_s=1e-3)
    with pytest.raises(ValueError, match=r"`normal_force=` = 1e308: .*dt = 0.005"):
        squeal.trajectory(law="mcmillan", normal_force=1e308, t_end=1.0, **brake)
