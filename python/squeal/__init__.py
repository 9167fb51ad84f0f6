"""squeal: basins of attraction of McMillan's friction oscillator (steady slip or stick-slip
"squeal") and of the Stribeck law with true stick (bSTAB's friction case), from Python.

The computing is the Rust library's (the same code as the ``squeal`` command, which this
package also installs); results come back as ``xarray.Dataset`` objects with the HDF5
file's names, coordinates, units and CF flag meanings, and as dataclasses.

* :func:`scan` and :func:`atlas` run a spec (a path, or a dict with the TOML file's tables)
  and return the file's Dataset; ``out=`` keeps the file (else it is written to a
  temporary folder and removed).
* :func:`basin_stability`: bSTAB/pyBasin-style shares per regime with standard errors
  from random initial conditions.
* :func:`ulc` (the unstable limit cycle) and :func:`critical` (the critical damping)
  return dataclasses; :func:`trajectory` returns one run as a Dataset over time.
* :func:`open` reads any file squeal writes.

The GIL is released while computing. Ctrl-C stops a run cleanly: ``KeyboardInterrupt`` is
raised after the blocks in flight are journalled next to ``out``, and the same call with
``resume=True`` finishes it. Bad input raises ``ValueError`` with the command line's message.
"""

from __future__ import annotations

import dataclasses
import json
import math
import numbers
import os
import sys
import tempfile
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Optional, Union

from . import _args, _squeal

__version__: str = _squeal.__version__

__all__ = [
    "BasinStability",
    "Critical",
    "UnstableCycle",
    "atlas",
    "basin_stability",
    "critical",
    "flags",
    "open",
    "report",
    "scan",
    "trajectory",
    "ulc",
]

Spec = Union[str, os.PathLike, Mapping[str, Any]]

#: The regimes of a basin-stability report, in the file's order (squeal_scan::basin::REGIMES).
REGIMES = ("steady_slip", "stick_slip", "undecided", "slip_oscillation")


def _jsonable(v: Any) -> Any:
    """numpy scalars and arrays in a spec dict, as JSON numbers and lists; paths
    (``os.PathLike``) as strings."""
    if hasattr(v, "tolist"):
        return v.tolist()
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    raise TypeError(f"spec value {v!r}: expected numbers, strings, lists or tables")


def _check_values(table: Mapping[str, Any], where: str) -> None:
    """Refuses a value no key takes, naming its key (``model.nu``): ``None``, or a number
    that is not finite (JSON has neither, and the parser's "expected value at line 1 column
    51" named no key)."""
    for k, v in table.items():
        key = f"{where}.{k}" if where else str(k)
        if isinstance(v, Mapping):
            _check_values(v, key)
            continue
        for x in _leaves(v):
            if x is None:
                raise ValueError(f"spec: `{key}` = None: expected a value")
            if isinstance(x, float) and not math.isfinite(x):
                raise ValueError(f"spec: `{key}` = {x}: expected a finite number")


def _leaves(v: Any) -> list:
    """The numbers (and other scalars) of a value, lists within lists included (the rows
    of ``friction_table=``, a numpy array's elements)."""
    items = v.tolist() if hasattr(v, "tolist") else v
    if isinstance(items, (list, tuple)):
        return [x for item in items for x in _leaves(item)]
    return [items]


def _real(name: str, v: Any) -> float:
    """A number argument of a helper, or a ``TypeError`` naming the keyword ``name=``."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(f"{name}=: expected a number, not {type(v).__name__}")
    return float(v)


def _spec(spec: Spec) -> tuple[str, Optional[str]]:
    """(name used in messages, TOML text or None to read the file ``name``)."""
    if isinstance(spec, (str, os.PathLike)):
        return os.fspath(spec), None
    if isinstance(spec, Mapping):
        _check_values(spec, "")
        return "spec", _squeal.spec_toml(json.dumps(dict(spec), default=_jsonable))
    raise TypeError(f"spec= {spec!r:.60}: expected a path or a dict, not {type(spec).__name__}")


def open(path: Union[str, os.PathLike]) -> "xarray.Dataset":  # noqa: A001 (squeal.open)
    """Any file squeal writes (scan, sweep, sample, atlas, trajectory ``.h5``), loaded into
    memory as an ``xarray.Dataset``: its variables, dimension coordinates and attributes as
    stored (integers stay integers; enumerations keep ``flag_values``/``flag_meanings``).
    What ``squeal info`` refuses is refused first, in its words (``ValueError``), before
    anything opens the file: a FIFO or other non-regular file, a file that is not HDF5, a
    truncated one, an HDF5 file squeal did not write."""
    import xarray as xr

    path = _args.path("open", "path", path)
    _squeal.file_kind(path)
    with xr.open_dataset(
        path,
        engine="h5netcdf",
        mask_and_scale=False,
        decode_times=False,
        decode_timedelta=False,
    ) as ds:
        return ds.load()


def report(
    file: Union[str, os.PathLike],
    out: Optional[Union[str, os.PathLike]] = None,
    force: bool = False,
) -> Path:
    """Writes the self-contained interactive page of a scan, atlas or trajectory file (what
    ``squeal report FILE.h5`` writes): one HTML file that opens offline in any browser, with
    the maps, chart or run, the values under the pointer, and the provenance. ``out``
    defaults to the file's name with ``.html``; an existing page is refused unless
    ``force=True``. Returns the page's path."""
    file = _args.path("report", "file", file)
    out = None if out is None else _args.path("report", "out", out)
    force = _args.flag("report", "force", force)
    return Path(_squeal.report(file, out, force))


def flags(da) -> dict:
    """``{value: meaning}`` of a flagged integer variable (CF ``flag_values`` and
    ``flag_meanings``), e.g. ``{0: 'undecided', 1: 'steady_slip', 2: 'stick_slip', 255:
    'not_computed'}`` for a scan's ``labels``."""
    attrs = getattr(da, "attrs", None)
    if not isinstance(attrs, Mapping) or "flag_meanings" not in attrs:
        raise TypeError(
            f"squeal.flags: da= {da!r:.60}: expected a flagged variable of a Dataset "
            "(with flag_values and flag_meanings), e.g. ds['labels']"
        )
    meanings = attrs["flag_meanings"].split()
    return {int(v): m for v, m in zip(da.attrs["flag_values"], meanings)}


def _run(kind: str, spec: Spec, out, resume: bool, force: bool, allow_long: bool):
    resume, force = _args.flag(kind, "resume", resume), _args.flag(kind, "force", force)
    allow_long = _args.flag(kind, "allow_long", allow_long)
    out = None if out is None else _args.path(kind, "out", out)
    name, text = _spec(spec)
    run = getattr(_squeal, kind)
    if out is None:
        if resume:
            raise ValueError("resume=True needs out=: the file of the interrupted run")
        with tempfile.TemporaryDirectory(prefix="squeal-") as d:
            path = Path(d) / f"{kind}.h5"
            try:
                run(name, text, str(path), False, False, allow_long)
            except KeyboardInterrupt:
                print("squeal: interrupted; pass out= to keep a resumable run", file=sys.stderr)
                raise
            return open(path)
    try:
        computed = run(name, text, os.fspath(out), resume, force, allow_long)
    except KeyboardInterrupt:
        print(
            f"squeal: interrupted; the finished work is kept in {os.fspath(out)}.journal. "
            f"Finish with: squeal.{kind}(..., out={os.fspath(out)!r}, resume=True)",
            file=sys.stderr,
        )
        raise
    if computed is None:
        # As the command line says it: a finished file of the same spec, nothing computed.
        print(f"squeal: {os.fspath(out)} is up to date (made from the same spec)", file=sys.stderr)
    return open(out)


def scan(
    spec: Spec, out=None, *, resume: bool = False, force: bool = False, allow_long: bool = False
):
    """Runs a scan spec (``squeal scan``): a basin map, a sweep of maps or random samples.

    ``spec``: a path to a TOML spec or a dict of its tables, e.g.
    ``{"version": 1, "model": {"law": "mcmillan", "nu": 1e-2}, "grid": {...},
    "output": {"path": "x.h5"}}`` (``output.path`` is required by the spec format but the
    file goes to ``out``). ``out``: keep the HDF5 file there (``force`` overwrites it;
    ``resume`` finishes an interrupted run of it). Like make, a finished ``out`` of the same
    spec is up to date, with or without ``resume``: nothing is computed. A file of another
    spec or kind is refused without ``force``. Work estimated over 30 days at the documented
    rates is refused before anything runs unless ``allow_long=True`` (``--allow-long``).
    Returns the file as a Dataset."""
    return _run("scan", spec, out, resume, force, allow_long)


def atlas(
    spec: Spec, out=None, *, resume: bool = False, force: bool = False, allow_long: bool = False
):
    """Runs an atlas spec (``squeal atlas``): figures of merit, regimes, the fold and the
    critical damping over a design space. Arguments as for :func:`scan`."""
    return _run("atlas", spec, out, resume, force, allow_long)


@dataclasses.dataclass
class BasinStability:
    """Basin stability (Menck et al. 2013; bSTAB, pyBasin): the share of random initial
    conditions in a region ending in each regime, with the binomial standard error
    ``sqrt(p (1 - p) / n)``. For a sweep, ``shares[r]``, ``errors[r]`` are arrays over
    ``values`` of the swept parameter ``parameter`` (a physical system's key as swept: ``c``
    in N s/m, ``v_belt`` in m/s, ``mu_s``, or ``tau_si`` in s for ``tau_s=``), or, when several keys are swept, over ``parameter =
    "map"`` (each swept key a coordinate over ``map`` in ``dataset``); else floats."""

    shares: dict
    errors: dict
    n: int
    seed: int
    region: tuple
    parameter: Optional[str] = None
    values: Any = None
    dataset: Any = dataclasses.field(default=None, repr=False)


def _swept(ds) -> Optional[str]:
    """The sweep dimension of a scan Dataset (None for one map): the swept key, or ``map``
    when several keys are swept (each then a coordinate over ``map``)."""
    dims = [d for d in ds["labels"].dims if d not in ("v0", "x0", "sample")]
    return dims[0] if dims and dims[0] in ds.coords else None


def basin_stability(
    law: str = "stribeck",
    *,
    n: int = 5000,
    seed: int = 1,
    region: Optional[Sequence[Sequence[float]]] = None,
    out=None,
    integration: Optional[Mapping[str, Any]] = None,
    classifier: Optional[Mapping[str, Any]] = None,
    physical: Optional[Mapping[str, Any]] = None,
    **params: Any,
) -> BasinStability:
    """Shares per regime of ``n`` uniform random initial conditions (seeded) in
    ``region = ((x0_min, x0_max), (v0_min, v0_max))``: bSTAB's estimator, squeal's
    classifier. ``params`` are the model's (``xi``, ``v_d``, ``mu_d``, ... for the Stribeck
    law; ``nu``, ``lambda``, ... for McMillan's; for ``law="table"`` its curve as
    ``friction_table=[(s, mu), ...]`` or ``friction_csv="pad.csv"``, relative to the working
    folder); any of them may be a list or array (a
    sweep, e.g. ``v_d=numpy.linspace(0.8, 2.225, 20)``, the belt-speed study; several
    make one map per point of their product, over the Dataset's ``map``).
    Or, for McMillan's laws and Coulomb, the physical system in SI units, as keywords
    (``m, k, c, v_belt, mu_k, mu_s, tau_s`` and ``g`` or ``normal_force``, as the command
    line's flags; ``c``, ``v_belt``, ``mu_s`` and ``tau_s`` may be swept) or as ``physical=`` (a ``[physical]``
    table); then ``region`` is in m and m/s and must be given.
    Defaults: bSTAB's friction case region and 5000 samples."""
    names = _Names("basin_stability")
    n = _args.whole("basin_stability", "n", n, lo=1)
    seed = _args.whole("basin_stability", "seed", seed)
    tables = _model_tables({"law": law, **params}, physical, names)
    if region is None:
        if "physical" in tables:
            raise ValueError(
                "squeal.basin_stability: region=: give the region in m and m/s for a "
                "physical system (the default is bSTAB's, in the model's units)"
            )
        region = ((-2.0, 2.0), (0.0, 2.0))
    (x_lo, x_hi), (v_lo, v_hi) = _region(region)
    names.keys["sample.region.x0"] = "region="
    names.keys["sample.region.v0"] = "region="
    spec = {
        "version": 1,
        "name": "basin-stability",
        **tables,
        "sample": {
            "kind": "random",
            "n": n,
            "seed": seed,
            "region": {"x0": [x_lo, x_hi], "v0": [v_lo, v_hi]},
        },
        "output": {"path": "basin-stability.h5"},
    }
    for table, given in (("integration", integration), ("classifier", classifier)):
        if given is not None:
            spec[table] = _args.settings("basin_stability", table, given)
            for key in spec[table]:
                names.keys[f"{table}.{key}"] = f"{table}={{{key!r}: ...}}"
    ds = names(scan, spec, out)
    dim = _swept(ds)
    # A physical sweep's parameter as the caller swept it: the Dataset's SI coordinate over
    # the model's key (c in N s/m over nu or xi, v_belt in m/s, mu_s over phi, tau_si in s).
    twin = _squeal.si_twin(dim) if dim else None
    shown = twin[1] if twin and twin[1] in ds.coords else dim

    def pick(var):
        a = ds[var].values
        return a if dim else float(a.reshape(-1)[0])

    return BasinStability(
        shares={r: pick(f"basin_stability_{r}") for r in REGIMES},
        errors={r: pick(f"basin_stability_{r}_se") for r in REGIMES},
        n=n,
        seed=seed,
        region=((x_lo, x_hi), (v_lo, v_hi)),
        parameter=shown,
        values=ds[shown].values if shown else None,
        dataset=ds,
    )


def _region(region: Any) -> tuple:
    """``region=``: two pairs of numbers, ``((x0_min, x0_max), (v0_min, v0_max))``."""
    shaped = hasattr(region, "__len__") and not isinstance(region, (str, bytes, Mapping))
    if not shaped or len(region) != 2:
        raise ValueError(
            f"squeal.basin_stability: region= {region!r}: expected "
            "((x0_min, x0_max), (v0_min, v0_max))"
        )
    return tuple(_args.pair("basin_stability", "region", r) for r in region)


#: The physical system's keywords (the command line's ``--m ... --normal-force``) and the
#: ``[physical]`` keys they stand for: the surface time in seconds is ``tau_s`` (as
#: ``--tau-s``), since ``tau`` is the model's nondimensional ``tau'``.
_PHYSICAL = {
    "m": "m",
    "k": "k",
    "c": "c",
    "v_belt": "v_belt",
    "mu_k": "mu_k",
    "mu_s": "mu_s",
    "tau_s": "tau",
    "g": "g",
    "normal_force": "normal_force",
}


#: The table law's curve (``law="table"``): with the physical system its slip speeds are in
#: m/s and it goes to the ``[physical]`` table, else to ``[model]``.
_TABLE_KEYS = ("friction_table", "friction_csv")


class _Names:
    """Where each spec key of a helper's call came from: the Python keyword (``m=``,
    ``tau_s=``) or the ``physical=`` mapping (``physical["tau"]``), so that an error names
    what the caller wrote, not a TOML table the caller never saw."""

    def __init__(self, helper: str):
        self.helper = helper
        self.keys: dict[str, str] = {}

    def rename(self, e: ValueError) -> ValueError:
        import re

        text = re.sub(
            r"`((?:physical|model|sample\.region|integration|classifier)\.\w+)`",
            lambda m: f"`{self.keys.get(m.group(1), m.group(1))}`",
            str(e),
        )
        if self.keys:
            # The spec was built from the call's keywords: name the call, not "spec".
            text = text.replace("spec: ", f"squeal.{self.helper}: ", 1)
        return ValueError(text)

    def __call__(self, f, *args):
        # The library's warnings (a unit slip, said before anything runs) name the spec's
        # keys too: said again, outside the recording, with the caller's.
        said: list = []
        try:
            with warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                return f(*args)
        except ValueError as e:
            raise self.rename(e) from None
        finally:
            for w in said:
                text = self.rename(ValueError(str(w.message))).args[0]
                warnings.warn(text, w.category, stacklevel=3)


def _checked(helper: str, model: dict[str, Any], physical) -> tuple[dict, Optional[dict]]:
    """The keywords ``model`` and the mapping ``physical`` with each value checked by its
    keyword (:mod:`squeal._args`): the law one of the library's, every other key a law's,
    the physical system's or a measured curve, a number or numbers to sweep, a curve's
    rows of numbers or its file as a path."""
    _args.known(helper, model, _PHYSICAL, _TABLE_KEYS)

    def one(k: str, v: Any, shown: str) -> Any:
        if k == "friction_csv":
            return _args.path(helper, shown, v)
        if k == "friction_table":
            return _args.table_rows(helper, shown, v)
        return _args.value(helper, shown, v)

    out = {k: _args.law(helper, v) if k == "law" else one(k, v, k) for k, v in model.items()}
    if physical is None:
        return out, None
    if not isinstance(physical, Mapping):
        raise TypeError(f"squeal.{helper}: physical= {physical!r}: expected a dict of the "
                        "[physical] table's keys")
    return out, {k: one(k, v, f"physical[{k!r}]") for k, v in physical.items()}


def _model_tables(
    model: dict[str, Any],
    physical: Optional[Mapping[str, Any]],
    names: _Names,
    defaults: bool = False,
) -> dict[str, Any]:
    """The ``[model]`` and ``[physical]`` tables of the keywords ``model`` (the physical
    keys among them, :data:`_PHYSICAL`) and the mapping ``physical`` (its keys as the
    ``[physical]`` table's); ``names`` learns which keyword each spec key came from. With
    ``defaults`` (the helpers of one parameter point, as the command line's flags), the law
    and the law's keys not given take the library's defaults (``law="mcmillan"``,
    ``nu=1e-3``)."""
    if defaults:
        model.setdefault("law", _args.laws()["default"])
    model, physical = _checked(names.helper, model, physical)
    given = {k: model.pop(k) for k in list(model) if k in _PHYSICAL}
    if given and physical is not None:
        raise ValueError(
            f"squeal.{names.helper}: give the physical system as keywords "
            f"({', '.join(sorted(given))}) or as physical=, not both"
        )
    tables: dict[str, Any] = {"model": dict(model)}
    for k in model:
        names.keys[f"model.{k}"] = f"{k}="
    if given:
        tables["physical"] = {_PHYSICAL[k]: v for k, v in given.items()}
        for k in given:
            names.keys[f"physical.{_PHYSICAL[k]}"] = f"{k}="
        # A measured curve goes with the physical system, its slip speeds in m/s.
        for k in _TABLE_KEYS:
            if k in tables["model"]:
                tables["physical"][k] = tables["model"].pop(k)
                names.keys[f"physical.{k}"] = f"{k}="
    elif physical is not None:
        tables["physical"] = dict(physical)
        for k in physical:
            names.keys[f"physical.{k}"] = f"physical[{k!r}]"
    if "physical" in tables:
        # The model's own parameters are the physical system's (nu from c, ...).
        for k in tables["model"]:
            if k != "law":
                raise ValueError(
                    f"squeal.{names.helper}: {k}= is a nondimensional parameter; with the "
                    f"physical system ({', '.join(_PHYSICAL)}) it follows from them "
                    "(tau_s= is the surface time in seconds)"
                )
    elif defaults and "law" in tables["model"]:
        law = _args.laws()["laws"][tables["model"]["law"]]
        for k, v in law["defaults"].items():
            tables["model"].setdefault(k, v)
    return tables


def _model_spec(
    spec: Optional[Spec],
    model: dict[str, Any],
    extra: Mapping[str, Any],
    names: _Names,
    physical: Optional[Mapping[str, Any]] = None,
):
    """A spec for one parameter point: ``spec`` as given, or the model ``model`` (with its
    physical keys or ``physical``, :func:`_model_tables`) on a one-cell grid (as the command
    line builds one from its flags)."""
    if spec is not None:
        if model or physical is not None:
            got = sorted(model) + (["physical"] if physical is not None else [])
            raise ValueError(
                "give either spec= or the model's parameters, not both "
                f"(got {', '.join(got)})"
            )
        return spec
    one = {"min": 0.0, "max": 0.0, "count": 1}
    s = {
        "version": 1,
        **_model_tables(model, physical, names, defaults=True),
        "grid": {"x0": one, "v0": one},
        "output": {"path": "unused.h5"},
    }
    s.update({k: _args.settings(names.helper, k, v) for k, v in extra.items() if v is not None})
    for table in extra:
        for key in s.get(table, {}):
            names.keys[f"{table}.{key}"] = f"{table}={{{key!r}: ...}}"
    return s


@dataclasses.dataclass
class UnstableCycle:
    """The unstable limit cycle (the basin boundary) as a periodic orbit: its crossing
    ``r_section`` of the section ``x = x*, x' > 0`` and bisection ``bracket``, period,
    angular frequency ``omega``, extents, area, Floquet ``multiplier`` (> 1: unstable),
    whether it encloses the state at rest, the ``dt / 2`` check, and the closed curve
    ``x``, ``v`` (numpy arrays). ``report`` holds every field the library reports."""

    r_section: float
    bracket: tuple
    period: float
    omega: float
    x_range: tuple
    v_range: tuple
    distance_plus_x: float
    area: float
    multiplier: float
    encloses_origin: bool
    x: Any = dataclasses.field(repr=False)
    v: Any = dataclasses.field(repr=False)
    report: dict = dataclasses.field(repr=False, default_factory=dict)


def ulc(
    spec: Optional[Spec] = None,
    *,
    map: int = 0,  # noqa: A002 (the command line's --map)
    r_max: float = 6.0,
    rtol: float = 1e-10,
    check_half_dt: bool = True,
    integration: Optional[Mapping[str, Any]] = None,
    physical: Optional[Mapping[str, Any]] = None,
    **model: Any,
) -> UnstableCycle:
    """Locates the unstable limit cycle (``squeal ulc``) of the model given by its
    parameters (``law="mcmillan", nu=1e-2``; ``integration={"dt": ...}``; the tabulated law
    as ``law="table", friction_table=[(0.0, 0.6), (0.5, 0.45), (2.0, 0.4)]`` or
    ``friction_csv="pad.csv"``, slip speed and mu, the first row at slip speed 0), or by its
    physical system in SI units (``m=0.8, k=2e5, c=20, v_belt=0.3, mu_k=0.38, mu_s=0.48,
    tau_s=5e-4, normal_force=1500``, the command line's flags; or ``physical=`` a
    ``[physical]`` table), or of map ``map`` of a scan ``spec``. Errors name the keyword."""
    import numpy as np

    names = _Names("ulc")
    map = _args.whole("ulc", "map", map)  # noqa: A001
    check_half_dt = _args.flag("ulc", "check_half_dt", check_half_dt)
    s = _model_spec(spec, model, {"integration": integration}, names, physical)
    name, text = names(_spec, s)
    r_max, rtol = _real("r_max", r_max), _real("rtol", rtol)
    rep = json.loads(names(_squeal.ulc, name, text, map, r_max, rtol, check_half_dt))
    return UnstableCycle(
        r_section=rep["r_section"],
        bracket=tuple(rep["bracket"]),
        period=rep["period"],
        omega=rep["omega"],
        x_range=tuple(rep["x_range"]),
        v_range=tuple(rep["v_range"]),
        distance_plus_x=rep["distance_plus_x"],
        area=rep["area"],
        multiplier=rep["multiplier"],
        encloses_origin=rep["encloses_origin"],
        x=np.asarray(rep["curve"]["x"]),
        v=np.asarray(rep["curve"]["v"]),
        report=rep,
    )


@dataclasses.dataclass
class Critical:
    """A stability boundary in one parameter (``squeal critical``): with ``fold=False`` the
    value above which the start ``point`` stops squealing (below it, it squeals), with
    ``fold=True`` the fold (above it no start of the spread squeals). ``value`` is the
    geometric middle of ``bracket``, after ``evaluations`` bisection steps (runs, where
    ``by == "runs"``); ``half_dt_holds`` says whether the bracket holds at ``dt / 2``
    (``None``: not checked). ``by`` says who answered: ``"shortcut"`` (the unstable cycle,
    the band's crisis; ``confirmed`` and ``confirmation`` give the runs at its bracket) or
    ``"runs"`` (outside the checked region, or where a run refuted the shortcut: ``why``;
    the bracket then covers ``dt / 2``), as ``squeal critical`` prints
    (crates/core/MODEL.md section 13). ``step_sensitivity`` is the share of the starts at
    the bracket's ends (the runs' bracket, or the shortcut's confirmed by runs) whose fate
    changes at ``dt / 2`` (of ``step_sensitivity_compared`` starts run at both steps,
    ``step_sensitivity_changed`` changed; ``step_sensitivity_se`` its binomial standard
    error; ``None`` where no run checked it), as ``squeal critical --json`` names them."""

    parameter: str
    value: float
    bracket: tuple
    evaluations: int
    point: tuple
    fold: bool = False
    half_dt_holds: Optional[bool] = None
    by: str = "shortcut"
    confirmed: Optional[bool] = None
    confirmation: Optional[str] = None
    why: Optional[str] = None
    step_sensitivity: Optional[float] = None
    step_sensitivity_se: Optional[float] = None
    step_sensitivity_changed: Optional[int] = None
    step_sensitivity_compared: Optional[int] = None


#: The parameters ``critical`` bisects in: McMillan's names and the laws with true stick's
#: (the library refuses a name under a law that is not its, as ``squeal critical --in``).
_BOUNDARY_KEYS = ("nu", "lambda", "xi", "v_d")


def critical(
    spec: Optional[Spec] = None,
    *,
    x0: float = 0.0,
    v0: float = 0.0,
    parameter: str = "nu",
    fold: bool = False,
    bracket: Optional[Sequence[float]] = None,
    rtol: float = 1e-4,
    horizon: float = 20000.0,
    map: int = 0,  # noqa: A002 (the command line's --map)
    integration: Optional[Mapping[str, Any]] = None,
    physical: Optional[Mapping[str, Any]] = None,
    **model: Any,
) -> Critical:
    """The critical value of ``parameter`` for the state ``(x0, v0)``, or with ``fold=True``
    the fold of cycles (``squeal critical [--fold] [--in PARAMETER]``), bisected over
    ``bracket`` (default: the command line's, ``(1e-3, 5e-2)`` in ``nu``/``xi``,
    ``(0.5, 6)`` in ``lambda``/``v_d``; ``nu`` is ``xi`` and ``lambda`` is ``v_d`` under the
    laws with true stick). The model as for :func:`ulc`, its parameters at the command
    line's defaults where not given (with the physical system, the bracket stays in ``nu``
    or ``lambda``, and ``x0``, ``v0`` are in m and m/s, as on the command line). The
    answer passes the command line's gate: confirmed by runs
    to ``horizon`` (nondimensional time), or found by them (``Critical.by``); without
    ``bracket`` the runs raise its top while a start still squeals there."""
    if not isinstance(parameter, str) or parameter not in _BOUNDARY_KEYS:
        raise ValueError(
            f"squeal.critical: parameter= {parameter!r}: expected one of "
            f"{', '.join(repr(k) for k in _BOUNDARY_KEYS)}"
        )
    which = _args.whole("critical", "map", map)
    fold = _args.flag("critical", "fold", fold)
    if bracket is not None:
        bracket = _args.pair("critical", "bracket", bracket)
    names = _Names("critical")
    s = _model_spec(spec, model, {"integration": integration}, names, physical)
    name, text = names(_spec, s)
    point = (_real("x0", x0), _real("v0", v0))
    rtol = _real("rtol", rtol)
    horizon = _real("horizon", horizon)
    search = (parameter, fold, rtol)
    b = json.loads(names(_squeal.boundary, name, text, which, point, search, bracket, horizon))
    lo = b["range"][0]
    if b["status"] == "below_range":
        what = "nothing squeals there already" if fold else f"{point} is quiet there already"
        raise ValueError(f"bracket low end {parameter} = {lo}: {what}; lower it")
    if b["status"] != "found":
        top = b["bracket"][1]
        raise ValueError(f"bracket high end {parameter} = {top}: it still squeals there; raise it")
    return Critical(
        parameter,
        b["value"],
        tuple(b["bracket"]),
        b["evaluations"],
        point,
        fold,
        b["half_dt_holds"],
        b["by"],
        b.get("confirmed"),
        b.get("confirmation"),
        b.get("why"),
        b.get("step_sensitivity"),
        b.get("step_sensitivity_se"),
        b.get("step_sensitivity_changed"),
        b.get("step_sensitivity_compared"),
    )


def trajectory(
    spec: Optional[Spec] = None,
    *,
    x0: float = 0.0,
    v0: float = 0.0,
    t_end: float = 1000.0,
    every: Optional[int] = None,
    out=None,
    force: bool = False,
    map: int = 0,  # noqa: A002 (the command line's --map)
    integration: Optional[Mapping[str, Any]] = None,
    physical: Optional[Mapping[str, Any]] = None,
    **model: Any,
):
    """One run from ``(x0, v0)`` to ``t_end`` (``squeal trajectory``) as a Dataset over the
    time ``t``: ``x``, ``v``, ``a`` and the friction ``force``, every ``every``-th step
    (``None``: the command line's default without ``--every``, at least 100 samples per
    natural period and at most 100000 in all; the file's ``sampling`` says which), with
    the run's settings as attributes and the start's label (the one ``squeal scan`` and
    ``squeal classify`` give it: decided at the start where the unstable cycle's side decides
    it, else the classifier's verdict on the run) in ``regime``, ``reason``, ``t_decision``
    and ``t_squeal`` (the time on stick-slip before
    the run settled, as scans store it per cell: 0 never stuck, ``inf`` stick-slip for good,
    -1 not known). The model as for :func:`ulc` (with the physical system ``x0``, ``v0``
    are in m and m/s, as on the command line; the Dataset is in the model's units, with
    ``length_unit``, ``velocity_unit``, ``time_unit`` and the system's ``physical_<key>``
    attributes); ``out`` keeps the file (the schema of ``squeal trajectory --out run.h5``;
    an existing file there is refused unless ``force=True``, as on the command line)."""
    names = _Names("trajectory")
    map = _args.whole("trajectory", "map", map)  # noqa: A001
    force = _args.flag("trajectory", "force", force)
    out = None if out is None else _args.path("trajectory", "out", out)
    s = _model_spec(spec, model, {"integration": integration}, names, physical)
    name, text = names(_spec, s)

    point = (_real("x0", x0), _real("v0", v0))
    every = None if every is None else _args.whole("trajectory", "every", every, lo=1)
    span = (_real("t_end", t_end), every)

    def run(path):
        verdict = names(_squeal.trajectory, name, text, map, point, span, str(path), force)
        ds = open(path)
        ds.attrs.update(zip(("regime", "reason", "t_decision", "t_squeal"), verdict))
        return ds

    if out is not None:
        return run(out)
    with tempfile.TemporaryDirectory(prefix="squeal-") as d:
        return run(Path(d) / "trajectory.h5")


def __dir__() -> list:
    """What ``dir(squeal)`` lists: the package's API (``__all__``) and its version, not the
    modules and names it uses inside (``os``, ``json``, ``Any``, ...)."""
    return sorted([*__all__, "__version__"])
