"""A seeded, time-bounded fuzz run of the Python doors: every keyword of ``ulc``,
``critical``, ``trajectory``, ``basin_stability`` and ``scan`` given a value no key accepts
(NaN, infinities, a string, None, a list, a negative or huge count). Each case runs in a
fresh interpreter under a time limit and must end in a Python error (``ValueError`` or
``TypeError``) that names the keyword it came from, quickly (bad input is refused before any
computing), without a Rust panic, and without touching a file that was there before.

Seed and size: ``SQUEAL_FUZZ_SEED`` (default 32) and ``SQUEAL_FUZZ_CASES`` (default 60).
Run by scripts/ci/test-python.sh with the other tests of the package."""

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
