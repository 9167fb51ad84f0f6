"""A seeded, time-bounded fuzz run of the Python doors: every keyword of ``ulc``,
``critical``, ``trajectory``, ``basin_stability`` and ``scan`` given a value no key accepts
(NaN, infinities, a string, None, a list, a negative or huge count). Each case runs in a
fresh interpreter under a time limit and must end in a Python error (``ValueError`` or
``TypeError``) that names the keyword it came from, quickly (bad input is refused before any
computing), without a Rust panic, and without touching a file that was there before.

Seed and size: ``SQUEAL_FUZZ_SEED`` (default 32) and ``SQUEAL_FUZZ_CASES`` (default 60).

A second family, the Python type and shape cases (``shape_cases``), gives every argument
of every public function a value of the wrong type or shape, all of them (about 240 cases,
a few seconds in this interpreter: each is refused before anything runs).
Run by scripts/ci/test-python.sh with the other tests of the package (in .ci/run)."""

import os
import random
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

# Values that no numeric key of the package accepts: not finite, not a number, or a count
# out of any range (2**70 overflows every integer key; -1 is below every count's minimum).
HOSTILE = ["float('nan')", "float('inf')", "-float('inf')", "'x'", "None", "[]", "{}"]
COUNTS = ["-1", "2**70", "float('nan')", "'x'"]

# Each door with a valid base call (cheap when run) and the keywords to break: numeric
# keywords take HOSTILE values, count keywords COUNTS.
DOORS = {
    "ulc": ('law="mcmillan", nu=1e-2', ["nu", "lambda", "tau", "phi", "r_max", "rtol"], []),
    "critical": (
        'law="mcmillan"',
        ["x0", "v0", "rtol", "nu", "lambda", "tau", "phi"],
        [],
    ),
    "trajectory": (
        'law="mcmillan", nu=1e-2, t_end=5.0',
        ["x0", "v0", "t_end", "nu", "lambda", "tau", "phi"],
        ["every"],
    ),
    "basin_stability": (
        'law="stribeck", n=8',
        ["xi", "v_d", "mu_d", "mu_sd", "v_0"],
        ["n", "seed"],
    ),
}

# The physical system's keywords, each broken on its own in a valid pad (the brake of the
# README) through trajectory.
PAD = 'm=0.8, k=2e5, c=20.0, v_belt=0.3, mu_k=0.38, mu_s=0.48, tau_s=5e-4, normal_force=1500.0'
PHYSICAL = ["m", "k", "c", "v_belt", "mu_k", "mu_s", "tau_s", "normal_force"]


def cases(seed: int, n: int):
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        kind = rng.random()
        if kind < 0.75:
            door = rng.choice(sorted(DOORS))
            base, floats, counts = DOORS[door]
            # A keyword of the base call is broken by replacing it, not by repeating it.
            key = rng.choice(floats + counts)
            base = ", ".join(p for p in base.split(", ") if not p.startswith(key + "="))
            value = rng.choice(COUNTS if key in counts else HOSTILE)
            # `lambda` is a Python keyword: every broken key goes in as **{...}.
            call = f"squeal.{door}({base}, **{{{key!r}: {value}}})"
        else:
            key = rng.choice(PHYSICAL)
            value = rng.choice(HOSTILE)
            others = ", ".join(p for p in PAD.split(", ") if not p.startswith(key + "="))
            call = f'squeal.trajectory(law="mcmillan", t_end=5.0, {others}, **{{{key!r}: {value}}})'
        out.append((key, call))
    return out


SEED = int(os.environ.get("SQUEAL_FUZZ_SEED", "32"))
N = int(os.environ.get("SQUEAL_FUZZ_CASES", "60"))


@pytest.mark.parametrize("key,call", cases(SEED, N))
def test_a_hostile_keyword_is_refused_by_name(key, call, tmp_path):
    # A finished-looking file beside the run: it must be there, unchanged, afterwards.
    keep = tmp_path / "precious.h5"
    keep.write_bytes(b"not touched")
    code = textwrap.dedent(
        f"""
        import squeal
        try:
            {call}
        except (ValueError, TypeError) as e:
            print("REFUSED", e)
        else:
            print("ACCEPTED")
        """
    )
    p = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
    )
    said = p.stdout + p.stderr
    assert "panicked" not in said and "PanicException" not in said, (call, said)
    assert p.returncode == 0, (call, said)
    assert "REFUSED" in p.stdout, (call, said)
    # The message names the keyword the value came from (a key of a table, `region=`, or
    # the keyword itself).
    assert key in p.stdout, (call, p.stdout)
    assert keep.read_bytes() == b"not touched"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["precious.h5"], (call, list(tmp_path.iterdir()))


def test_the_cases_are_seeded():
    assert cases(7, 5) == cases(7, 5)
    assert Path(__file__).exists()


# The Python type and shape cases: every public function's arguments given a value of the
# wrong type or shape (a bool or a string for a number, a float or a bool for a count, a
# negative count, a tuple of the wrong length, None, NaN, a number for a path or a flag).
# Each is refused before anything runs, with ValueError or TypeError naming the argument;
# before, many raised OverflowError, a TOML parse error, "not enough values to unpack" or
# AttributeError, or ran truncated (n=200.9 ran 200 samples). In this interpreter: each
# refusal is immediate, and a case accepted by mistake runs a cheap base call.
NUMBER = ["True", "'1.5'", "None", "[1.0, 'x']", "b'1'", "object()"]
COUNT = ["True", "2.5", "-1", "'3'", "None", "2**70", "float('nan')"]
FLAG = ["'yes'", "'False'", "1", "None", "[True]"]
PAIR = ["(0.001,)", "(1e-3, 2e-2, 5e-2)", "'ab'", "5.0", "(True, 0.05)", "(0.001, 'x')"]
PATH = ["3", "True", "['a.h5']", "2.5"]
TABLE = ["'dt=0.1'", "[1]", "{'dt': True}", "{'dt': None}", "{'dt': [0.1]}"]

TINY_SPEC = (
    '{"version": 1, "model": {"law": "mcmillan", "nu": 1e-2}, "grid": {"x0": {"min": -1.0, '
    '"max": 1.0, "count": 2}, "v0": {"min": -1.0, "max": 1.0, "count": 2}}, "output": '
    '{"path": "t.h5"}}'
)
SHAPED = {
    # function: (base call's arguments, {argument: values})
    "scan": ({"spec": TINY_SPEC}, {"spec": ["3", "None", "[1]"], "out": PATH,
                                   "resume": FLAG, "force": FLAG, "allow_long": FLAG}),
    "atlas": ({"spec": "'nowhere.toml'"}, {"spec": ["3", "None"], "out": PATH, "force": FLAG}),
    "basin_stability": ({"n": "8"}, {"n": COUNT, "seed": COUNT, "law": ["'bogus'", "3", "None"],
                                     "region": ["((0.0, 1.0),)", "5.0", "((0.0,), (0.0, 1.0))",
                                                "'ab'"],
                                     "out": PATH, "integration": TABLE, "classifier": TABLE,
                                     "physical": ["'m=1'", "[1]"], "xi": NUMBER,
                                     "v_d": NUMBER}),
    "ulc": ({"law": "'mcmillan'", "nu": "1e-2"},
            {"map": COUNT, "r_max": NUMBER, "rtol": NUMBER, "check_half_dt": FLAG,
             "integration": TABLE, "lambda": NUMBER, "nu": NUMBER, "law": ["'bogus'", "3"],
             "friction_csv": PATH}),
    "critical": ({"law": "'mcmillan'", "horizon": "200.0", "rtol": "1e-2"},
                 {"x0": NUMBER, "v0": NUMBER, "fold": FLAG, "bracket": PAIR, "map": COUNT,
                  "parameter": ["'c'", "3", "None"], "horizon": NUMBER, "tau": NUMBER}),
    "trajectory": ({"law": "'mcmillan'", "t_end": "1.0"},
                   {"x0": NUMBER, "t_end": NUMBER,
                    # every=None is the command line's default stride (no --every).
                    "every": [c for c in COUNT if c != "None"], "map": COUNT, "out": PATH,
                    "force": FLAG, "integration": TABLE, "phi": NUMBER, "m": NUMBER,
                    "friction_table": ["'abc'", "5.0", "[(0.0, 'x')]"]}),
    "open": ({}, {"path": PATH + ["None"]}),
    "report": ({"file": "'nowhere.h5'"}, {"file": PATH + ["None"], "out": PATH, "force": FLAG}),
    "flags": ({}, {"da": ["3", "None", "'labels'"]}),
}


def shape_cases():
    out = []
    for fn, (base, args) in sorted(SHAPED.items()):
        for arg, values in sorted(args.items()):
            for v in values:
                kept = {**{k: e for k, e in base.items() if k != arg}, arg: v}
                inner = ", ".join(f"{k!r}: {e}" for k, e in kept.items())
                # `lambda` is a Python keyword: every argument goes in as **{...}.
                out.append((arg, f"squeal.{fn}(**{{{inner}}})"))
    return out


@pytest.mark.parametrize("arg,call", shape_cases())
def test_a_wrong_type_or_shape_is_refused_naming_the_argument(arg, call, tmp_path, monkeypatch):
    import squeal

    monkeypatch.chdir(tmp_path)
    try:
        eval(call, {"squeal": squeal})
    except (ValueError, TypeError) as e:
        msg = str(e)
    else:
        pytest.fail(f"{call}: accepted")
    # Named as the caller wrote it: `n=`, `physical=`, `bracket=` (or `nu=` of a table).
    assert f"{arg}=" in msg, (call, msg)
    for internal in ("TOML", "unpack", "argument 'search'", "line 1 column"):
        assert internal not in msg, (call, msg)
    assert list(tmp_path.iterdir()) == [], (call, list(tmp_path.iterdir()))


def test_the_shape_cases_cover_every_public_function():
    import squeal

    functions = {n for n in squeal.__all__ if callable(getattr(squeal, n)) and n[0].islower()}
    assert functions == set(SHAPED), functions ^ set(SHAPED)
