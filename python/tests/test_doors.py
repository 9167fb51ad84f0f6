"""Python's door agrees with the command line's: the same defaults (law, nu, the critical
bisection's parameter), the same refusals in Python's words (counts that are not whole,
arguments of the wrong type or shape, foreign and broken files), missing output folders made
by every door, and paths taken as ``os.PathLike`` everywhere.

Run by scripts/ci/test-python.sh in a fresh venv with the wheel installed and no Rust."""

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import squeal

# README's clamped pad (section 4): 0.8 kg on a 200 kN/m mount, the disc at 0.3 m/s, 1.5 kN.
PAD = dict(m=0.8, k=2e5, v_belt=0.3, mu_k=0.38, mu_s=0.48, tau_s=5e-4, normal_force=1500.0)

# A small one-map scan (the hysteretic law at nu = 1e-2, 3 x 2 cells).
TINY = {
    "version": 1,
    "model": {"law": "mcmillan", "nu": 1e-2},
    "grid": {"x0": {"min": -1.0, "max": 1.0, "count": 3},
             "v0": {"min": -1.0, "max": 1.0, "count": 2}},
    "output": {"path": "tiny.h5"},
}


def cli(*args, cwd):
    """The `squeal` command installed with the wheel."""
    exe = shutil.which("squeal")
    assert exe, "the wheel did not put `squeal` on PATH"
    return subprocess.run([exe, *args], cwd=cwd, capture_output=True, text=True, timeout=600)


# --- critical's parameter under the laws with true stick ------------------------------


@pytest.mark.parametrize("law", ["stribeck", "cubic"])
def test_critical_of_a_true_stick_law_bisects_xi_as_the_cli_does(law, tmp_path):
    # Before: "`nu=` = given: a key of law = ...", though nu was never given (Python set the
    # bisected key to the bracket's low end under McMillan's name). The command line bisects
    # xi by default (--in nu is xi under these laws).
    k = squeal.critical(law=law, x0=-1.0, v0=0.5, rtol=1e-3)
    assert k.parameter in ("nu", "xi")
    r = cli("critical", "--law", law, "--x0", "-1", "--v0", "0.5", "--rtol", "1e-3", "--json",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert k.value == json.loads(r.stdout)["xi"]


def test_critical_of_the_table_law_bisects_xi(tmp_path):
    csv = tmp_path / "pad.csv"
    csv.write_text("slip_speed,mu\n0,0.6\n0.5,0.45\n2,0.4\n")
    k = squeal.critical(law="table", friction_csv=csv, x0=-1.0, v0=0.5, rtol=1e-3)
    r = cli("critical", "--law", "table", "--friction-csv", str(csv), "--x0", "-1", "--v0",
            "0.5", "--rtol", "1e-3", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    # The command line's JSON names the table law's damping `nu` (the Stribeck law's `xi`).
    assert k.value == json.loads(r.stdout)["nu"]


def test_critical_refuses_xi_under_mcmillans_law_as_the_cli_does(tmp_path):
    r = cli("critical", "--in", "xi", cwd=tmp_path)
    assert r.returncode == 2 and "--in xi" in r.stderr, r.stderr
    with pytest.raises(ValueError, match=r"parameter= 'xi'.*mcmillan"):
        squeal.critical(law="mcmillan", parameter="xi")


# --- defaults -------------------------------------------------------------------------


def test_the_helpers_default_nu_as_the_cli_does(tmp_path):
    # Before: "`model.nu` = missing". The command line's default, crates/core/src/defaults.rs
    # NU = 1e-3 (the paper's Fig. 9).
    ds = squeal.trajectory(law="mcmillan", x0=0.5, t_end=2.0)
    assert ds.attrs["nu"] == 1e-3
    c = squeal.ulc(law="mcmillan")
    r = cli("ulc", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert c.r_section == json.loads(r.stdout)["r_section"]


def test_the_helpers_default_the_law_as_the_cli_does():
    # Before: a TOML error "missing field `law`". The command line's --law defaults to
    # mcmillan.
    ds = squeal.trajectory(c=100.0, x0=1e-4, t_end=2.0, **PAD)
    assert ds.attrs["law"] == "mcmillan"
    c = squeal.ulc(nu=1e-2)
    assert c.multiplier > 1


@pytest.mark.parametrize(
    "given, named",
    [
        ({"lambda": 0.0}, "lambda="),
        ({"tau": 0.0}, "tau="),
        ({"phi": 2.0}, "phi="),
        ({"integration": {"dt": 0.0}}, "integration={'dt'"),
    ],
)
def test_a_bad_value_is_named_not_hidden_behind_a_missing_nu(given, named):
    # Before, each of these said "`model.nu` = missing", hiding the value at fault.
    with pytest.raises(ValueError) as e:
        squeal.trajectory(law="mcmillan", t_end=1.0, **given)
    msg = str(e.value)
    assert named in msg and "missing" not in msg, msg


# --- whole numbers ----------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, keyword",
    [
        # Before: n=200.9 ran 200 samples, n=True ran 1, seed=1.7 ran seed 1.
        (lambda: squeal.basin_stability(n=200.9), "n="),
        (lambda: squeal.basin_stability(n=True), "n="),
        (lambda: squeal.basin_stability(n=8, seed=1.7), "seed="),
        (lambda: squeal.basin_stability(n=8, seed=-1), "seed="),
        (lambda: squeal.basin_stability(n=0), "n="),
        (lambda: squeal.basin_stability(n=8, seed=True), "seed="),
        # Before: a bare OverflowError, and map=1.5 a TypeError naming nothing.
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, map=-1), "map="),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, map=1.5), "map="),
        (lambda: squeal.critical(law="mcmillan", map=True), "map="),
        (lambda: squeal.trajectory(law="mcmillan", t_end=1.0, map=2**70), "map="),
        (lambda: squeal.trajectory(law="mcmillan", t_end=1.0, every=2.5), "every="),
    ],
)
def test_counts_must_be_whole_numbers(call, keyword):
    with pytest.raises(ValueError) as e:
        call()
    assert keyword in str(e.value), str(e.value)


def test_a_numpy_integer_is_a_whole_number():
    bs = squeal.basin_stability(n=np.int64(8), seed=np.uint32(2))
    assert bs.n == 8 and bs.seed == 2


# --- output folders ---------------------------------------------------------------------


def test_every_door_makes_missing_output_folders(tmp_path):
    # Before: scan(out=...) and basin_stability(out=...) failed with "cannot create the
    # lock", and `squeal merge -o` refused, while atlas and `squeal scan -o` made them.
    ds = squeal.scan(TINY, tmp_path / "a" / "b" / "tiny.h5")
    assert (tmp_path / "a" / "b" / "tiny.h5").is_file() and ds["labels"].size == 6
    squeal.basin_stability(n=8, out=tmp_path / "c" / "d" / "bs.h5")
    assert (tmp_path / "c" / "d" / "bs.h5").is_file()
    squeal.trajectory(law="mcmillan", t_end=1.0, out=tmp_path / "e" / "f" / "run.h5")
    assert (tmp_path / "e" / "f" / "run.h5").is_file()
    spec = tmp_path / "tiny.toml"
    spec.write_text(
        'version = 1\n[model]\nlaw = "mcmillan"\nnu = 1e-2\n[grid]\n'
        "x0 = { min = -1.0, max = 1.0, count = 3 }\nv0 = { min = -1.0, max = 1.0, count = 2 }\n"
        '[output]\npath = "tiny.h5"\n'
    )
    for k, out in [("1/2", "s1.h5"), ("2/2", "s2.h5")]:
        r = cli("scan", "tiny.toml", "--shard", k, "-o", out, "--quiet", cwd=tmp_path)
        assert r.returncode == 0, r.stderr
    r = cli("merge", "s1.h5", "s2.h5", "-o", "g/h/all.h5", "--no-render", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "g" / "h" / "all.h5").is_file()


# --- foreign and broken files -----------------------------------------------------------


def refused_alike(path, cwd):
    """squeal.open(path) raises ValueError in the words `squeal info path` prints."""
    r = cli("info", str(path), cwd=cwd)
    assert r.returncode != 0, r.stdout
    with pytest.raises(ValueError) as e:
        squeal.open(path)
    assert r.stderr.strip() == f"error: {e.value}"
    return str(e.value)


def test_open_refuses_what_info_refuses(tmp_path):
    import h5py

    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as f:
        f["x"] = np.arange(3.0)
    # Before: a Dataset with one variable x, where `squeal info` refuses the file.
    assert "not written by squeal" in refused_alike(foreign, tmp_path)
    text = tmp_path / "notes.h5"
    text.write_text("not HDF5\n")
    assert "not an HDF5 file" in refused_alike(text, tmp_path)
    good = tmp_path / "run.h5"
    squeal.trajectory(law="mcmillan", t_end=1.0, out=good)
    cut = tmp_path / "cut.h5"
    cut.write_bytes(good.read_bytes()[:2000])
    # Before: h5py's "Unable to synchronously open file (truncated file: ...)".
    assert "truncated or damaged" in refused_alike(cut, tmp_path)
    assert squeal.open(good).attrs["schema"]
    with pytest.raises(FileNotFoundError, match="nowhere"):
        squeal.open(tmp_path / "nowhere.h5")


def test_open_refuses_a_fifo_without_opening_it(tmp_path):
    # Before: squeal.open("fifo.h5") waited for a writer for ever. In a child process with a
    # time limit, so the old behaviour fails the test instead of hanging it.
    fifo = tmp_path / "fifo.h5"
    os.mkfifo(fifo)
    code = textwrap.dedent(
        f"""
        import squeal
        try:
            squeal.open({str(fifo)!r})
        except ValueError as e:
            print("REFUSED", e)
        """
    )
    try:
        p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           timeout=30)
    except subprocess.TimeoutExpired:
        pytest.fail("squeal.open blocked on a FIFO")
    assert "REFUSED" in p.stdout and "FIFO" in p.stdout, p.stdout + p.stderr


# --- paths ------------------------------------------------------------------------------


def test_every_path_argument_takes_a_path_object(tmp_path):
    csv = tmp_path / "pad.csv"
    csv.write_text("slip_speed,mu\n0,0.6\n0.5,0.45\n2,0.4\n")
    # Before: TypeError "spec value PosixPath(...): expected numbers, strings, ...".
    a = squeal.ulc(law="table", friction_csv=csv, v_d=0.5)
    b = squeal.ulc(law="table", friction_csv=str(csv), v_d=0.5)
    assert a.r_section == b.r_section
    run = squeal.trajectory(law="table", friction_csv=csv, v_d=0.5, t_end=1.0,
                            out=tmp_path / "run.h5")
    assert squeal.open(tmp_path / "run.h5").attrs["law"] == run.attrs["law"] == "table"


# --- errors in Python's words -----------------------------------------------------------


@pytest.mark.parametrize(
    "call, exc, named",
    [
        # Before: "TOML parse error at line ..." for each of the first four.
        (lambda: squeal.ulc(law="mcmillan", nu=True), TypeError, "nu="),
        (lambda: squeal.trajectory(law="mcmillan", t_end=1.0, **{**PAD, "c": 20.0,
                                                                 "normal_force": "1500"}),
         TypeError, "normal_force="),
        (lambda: squeal.ulc(law="bogus", nu=1e-2), ValueError, "law="),
        (lambda: squeal.ulc(law="mcmillan", nu=1e-2, bogus=1.0), TypeError, "bogus"),
        (lambda: squeal.basin_stability(n=8, vd=1.5), TypeError, "vd"),
        # Before: "argument 'search': ..." and "not enough values to unpack".
        (lambda: squeal.critical(law="mcmillan", fold="yes"), TypeError, "fold="),
        (lambda: squeal.critical(law="mcmillan", bracket=(0.001,)), ValueError, "bracket="),
        (lambda: squeal.basin_stability(n=8, region=((0.0, 1.0),)), ValueError, "region="),
        (lambda: squeal.ulc(law="mcmillan", check_half_dt="no"), TypeError, "check_half_dt="),
        (lambda: squeal.scan(TINY, force="yes"), TypeError, "force="),
        (lambda: squeal.trajectory(law="mcmillan", t_end=1.0, out=3), TypeError, "out="),
    ],
)
def test_errors_name_the_python_argument(call, exc, named):
    with pytest.raises(exc) as e:
        call()
    msg = str(e.value)
    assert named in msg, msg
    for internal in ("TOML", "argument 'search'", "unpack", "line 1"):
        assert internal not in msg, msg


def test_the_law_error_lists_the_laws():
    with pytest.raises(ValueError, match=r"law= 'bogus'.*mcmillan, .*table"):
        squeal.trajectory(law="bogus", t_end=1.0)


def test_a_run_keeping_too_many_samples_is_refused_as_on_the_cli(tmp_path):
    # `squeal trajectory --t-end 2e5 --out r.h5` refuses 4e7 kept samples (at most 2e7:
    # 2e5 / dt 0.005 = 4e7 steps, each kept with every=1); Python ran it, 1.6 GB in memory.
    # (every=1 asked for: without it both doors keep every 12th step, 3.3e6 samples.)
    r = cli("trajectory", "--t-end", "2e5", "--every", "1", "--out", "r.h5", cwd=tmp_path)
    assert r.returncode == 2 and "at most 20000000" in r.stderr, r.stderr
    with pytest.raises(ValueError, match=r"every= 1: 40000001 samples .*at most 20000000"):
        squeal.trajectory(law="mcmillan", t_end=2e5, every=1)
    assert list(tmp_path.iterdir()) == []
