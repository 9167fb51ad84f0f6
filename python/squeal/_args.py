"""The checks of the helpers' arguments, in Python's words: each refusal names the keyword
the caller wrote (``n=``, ``bracket=``, ``normal_force=``) and what it takes, before any
spec is built or anything runs. A value of the wrong type raises ``TypeError``, one of the
right type out of its range ``ValueError``; a count given as a bool or a float with a
fraction is refused (``ValueError``), not truncated (``n=200.9`` ran 200 samples).

The laws, their keys and defaults come from the library (``_squeal.laws()``, the same
defaults as the command line's flags), not from a copy here."""

from __future__ import annotations

import functools
import json
import math
import numbers
import os
from collections.abc import Mapping
from typing import Any

from . import _squeal

#: The largest count of a 64-bit unsigned integer (seeds, ``every``, ``map``), plus one.
U64 = 2**64


@functools.lru_cache(maxsize=None)
def laws() -> dict:
    """``{"default": law, "laws": {name: {"keys": [...], "defaults": {key: value}}}}``:
    the library's laws (crates/core), read once."""
    return json.loads(_squeal.laws())


def _shown(v: Any) -> str:
    """A value as a message quotes it: its repr, cut to 60 characters."""
    r = repr(v)
    return r if len(r) <= 60 else r[:57] + "..."


def whole(helper: str, name: str, v: Any, lo: int = 0, hi: int = U64) -> int:
    """A count argument: an integer (numpy's too) with ``lo <= v < hi``. A bool, a float or
    a string is refused (a float with no fraction too: the command line reads counts as
    integers)."""
    if isinstance(v, bool) or (isinstance(v, numbers.Real) and not isinstance(v, numbers.Integral)):
        raise ValueError(
            f"squeal.{helper}: {name}= {_shown(v)}: expected a whole number (an int) >= {lo}"
        )
    if not isinstance(v, numbers.Integral):
        raise TypeError(
            f"squeal.{helper}: {name}= {_shown(v)}: expected a whole number (an int), "
            f"not {type(v).__name__}"
        )
    if not lo <= int(v) < hi:
        top = "2**64" if hi == U64 else str(hi)
        raise ValueError(
            f"squeal.{helper}: {name}= {int(v)}: expected a whole number >= {lo} and below {top}"
        )
    return int(v)


def flag(helper: str, name: str, v: Any) -> bool:
    """A yes-or-no argument: ``True`` or ``False`` (numpy's bool too), nothing else (a
    string ``"no"`` is true to Python)."""
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return bool(v)
    raise TypeError(f"squeal.{helper}: {name}= {_shown(v)}: expected True or False")


def real(helper: str, name: str, v: Any) -> float:
    """A number argument (its range is the library's to check, naming ``name=``)."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(
            f"squeal.{helper}: {name}= {_shown(v)}: expected a number, not {type(v).__name__}"
        )
    return float(v)


def pair(helper: str, name: str, v: Any) -> tuple:
    """Two numbers, ``(low, high)``."""
    if isinstance(v, (str, bytes, Mapping)) or not hasattr(v, "__len__") or len(v) != 2:
        raise ValueError(f"squeal.{helper}: {name}= {_shown(v)}: expected two numbers (low, high)")
    return real(helper, name, v[0]), real(helper, name, v[1])


def path(helper: str, name: str, v: Any) -> str:
    """A path argument: a ``str`` or any ``os.PathLike`` (``pathlib.Path``)."""
    if isinstance(v, (str, os.PathLike)):
        p = os.fspath(v)
        if isinstance(p, str):
            return p
    raise TypeError(
        f"squeal.{helper}: {name}= {_shown(v)}: expected a path (str or os.PathLike), "
        f"not {type(v).__name__}"
    )


def law(helper: str, v: Any) -> str:
    """The ``law=`` argument: one of the library's laws."""
    names = list(laws()["laws"])
    if not isinstance(v, str):
        raise TypeError(f"squeal.{helper}: law= {_shown(v)}: expected one of {', '.join(names)}")
    if v not in names:
        raise ValueError(f"squeal.{helper}: law= {_shown(v)}: expected one of {', '.join(names)}")
    return v


def _is_number(x: Any) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def value(helper: str, name: str, v: Any) -> Any:
    """A parameter's value: a number, or numbers to sweep (a list, tuple or array of
    numbers, or a range table ``{"min": ..., "max": ..., "count": ...}``, checked by the
    spec). Returns it with arrays as lists."""
    if isinstance(v, Mapping):
        return dict(v)
    items = v.tolist() if hasattr(v, "tolist") else v
    if _is_number(items):
        return items
    if isinstance(items, (list, tuple)) and all(_is_number(x) for x in items):
        return list(items)
    raise TypeError(
        f"squeal.{helper}: {name}= {_shown(v)}: expected a number (or a list of numbers to "
        f"sweep), not {type(v).__name__}"
    )


def table_rows(helper: str, name: str, v: Any) -> Any:
    """``friction_table=``: rows of numbers (slip speed, mu); their count and order are the
    library's to check, naming the row."""
    items = v.tolist() if hasattr(v, "tolist") else v
    if isinstance(items, (list, tuple)) and all(
        isinstance(r, (list, tuple)) and all(_is_number(x) or x is None for x in r) for r in items
    ):
        return [list(r) for r in items]
    raise TypeError(
        f"squeal.{helper}: {name}= {_shown(v)}: expected rows of numbers (slip speed, mu)"
    )


def settings(helper: str, name: str, v: Any) -> dict:
    """``integration=`` or ``classifier=``: a mapping of the spec table's keys to numbers
    or words (no bools: no key of either table is yes-or-no)."""
    if not isinstance(v, Mapping):
        raise TypeError(f"squeal.{helper}: {name}= {_shown(v)}: expected a dict of its settings")
    for k, x in v.items():
        if isinstance(x, bool) or not (isinstance(x, (str, numbers.Real))):
            raise TypeError(
                f"squeal.{helper}: {name}= {{{k!r}: {_shown(x)}}}: expected a number or a word"
            )
        if isinstance(x, float) and not math.isfinite(x):
            raise ValueError(f"squeal.{helper}: {name}= {{{k!r}: {x}}}: expected a finite number")
    return dict(v)


def known(helper: str, keys: Mapping[str, Any], physical: Mapping[str, str], tables) -> None:
    """Refuses a keyword that is no law's key, no physical key and no curve, as Python
    refuses an unexpected keyword (``TypeError``), listing what the helper takes."""
    every = {k for law_ in laws()["laws"].values() for k in law_["keys"]}
    for k in keys:
        if k not in every and k not in physical and k not in tables and k != "law":
            raise TypeError(
                f"squeal.{helper}() got an unexpected keyword argument {k!r} (the laws' keys: "
                f"{', '.join(sorted(every))}; the physical system's: {', '.join(physical)}; "
                f"a measured curve: {', '.join(tables)})"
            )
