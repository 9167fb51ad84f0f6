#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = ["h5py", "numpy"]
# ///
"""Sizes of the differences between two folders of squeal's HDF5 files (OLD NEW), such as
the two that scripts/tools/same-results.sh leaves in target/same-results/run/{old,new}.

    python3 scripts/tools/same-results-summary.py OLD_DIR NEW_DIR [SPEC ...]
    python3 scripts/tools/same-results-summary.py --names OLD_DIR NEW_DIR [SPEC ...]

With --names it prints only the names that differ, as markdown tables (one row per name,
the specs where it differs; digits of record groups such as cycles/map_0003 shown as N):
the datasets, groups and attributes added or removed, the attributes whose value changed,
the datasets whose type or shape changed, and the datasets whose values changed. The
specs that are equal and those a binary did not write are listed first. Without it, for each file name present in both folders (or only the SPECs named), it prints:
- datasets and attributes found in one file only, and attributes whose text changed;
- for every dataset whose values differ: how many elements, the largest |new - old| and the
  largest |new - old| / |old| (over elements finite in both; elements finite in one file only
  are counted apart);
- where the file states an accuracy for the value, the largest change measured against it:
  a cycle's r_section against |cycle_half_dt_shift| (its change when dt halves), a fold
  against the new file's fold_*_err and whether each value lies inside the other's interval,
  a critical value against the old bracket's width, a basin fraction against its two
  standard errors combined, the mean section amplitude of a stick-slip window against the
  old window's spread (stick_r_max - stick_r_min), and whether the new critical value lies
  above the new fold's interval (fold + fold_err);
- for enumerations (labels, regime, reason, statuses): each change old -> new with its
  count, and for labels and regimes the changed cells by their coordinates;
- for text datasets (notes): each changed element;
- for numeric attributes of groups (cycle records): old -> new; for the TOML text of a
  cycle record, the keys whose lines changed.
Provenance (git_revision, squeal_version, created) and dimension-scale bookkeeping
(REFERENCE_LIST, DIMENSION_LIST) are left out; scripts/tools/h5_same.py reports those."""
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h5_same import pairs, same_values  # noqa: E402  (the walk over both files, written once)

SKIP_ATTRS = {"git_revision", "squeal_version", "software_version", "created", "version",
              "history", "date_created", "creation_time", "REFERENCE_LIST", "DIMENSION_LIST",
              "CLASS", "NAME", "_Netcdf4Dimid", "_Netcdf4Coordinates"}
LABELLED = ("labels", "regime")


def text(v):
    if isinstance(v, bytes):
        return v.decode()
    return str(v)


def short(v, n=90):
    s = text(v).replace("\n", " | ")
    return s if len(s) <= n else s[: n - 3] + "..."


def enum_names(ds):
    m = h5py.check_enum_dtype(ds.dtype)
    if m is None:
        meanings = ds.attrs.get("flag_meanings")
        values = ds.attrs.get("flag_values")
        if meanings is None or values is None:
            return None
        return {int(v): n for v, n in zip(values, text(meanings).split())}
    return {v: k for k, v in m.items()}


def coords(ds, idx):
    """The cell's coordinates by its dimension scales (name = value), else its index."""
    parts = []
    for axis, i in enumerate(idx):
        scales = ds.dims[axis] if axis < len(ds.dims) else []
        if len(scales):
            s = scales[0]
            name = s.name.strip("/")
            v = s[i] if s.ndim == 1 and i < s.shape[0] else i
            parts.append(f"{name}={v:.6g}" if isinstance(v, (float, np.floating)) else f"{name}={v}")
        else:
            parts.append(str(i))
    return "(" + ", ".join(parts) + ")"


def numeric_line(path, a, b):
    fa, fb = np.isfinite(a), np.isfinite(b)
    both = fa & fb
    diff = (a != b) & ~(np.isnan(a) & np.isnan(b))
    n = int(diff.sum())
    d = np.abs(b - a)[both]
    scale = np.abs(a)[both]
    rel = np.divide(d, scale, out=np.full_like(d, np.inf), where=scale > 0)
    rel = rel[d > 0]
    one_side = int((fa != fb).sum())
    line = f"{path}: {n} of {a.size} differ"
    if d.size and d.max() > 0:
        line += f"; max |d| {d.max():.3g}, max |d|/|old| {rel.max():.3g}"
    if one_side:
        line += f"; finite in one file only: {one_side}"
    return line


def accuracy(path, fa, fb):
    """Lines measuring a change against the accuracy the file states for it."""
    name = path.lstrip("/")
    out = []
    a, b = fa[name][()].astype(float), fb[name][()].astype(float)
    both = np.isfinite(a) & np.isfinite(b) & (a != b)
    if not both.any():
        return out
    d = np.abs(b - a)
    if name == "cycle_r_section" and "cycle_half_dt_shift" in fa:
        s = np.abs(fa["cycle_half_dt_shift"][()])
        r = d[both] / s[both]
        out.append(f"  against |old cycle_half_dt_shift|: max {r.max():.3g}, "
                   f"{int((r > 1).sum())} of {r.size} above 1")
    for kind in ("fold_", "critical_"):
        if not name.startswith(kind) or name.endswith(("_lo", "_hi", "_err", "_half_dt",
                                                       "_status", "_changes")):
            continue
        if any(name + end not in f for end in ("_lo", "_hi") for f in (fa, fb)):
            continue  # a figure of the fold without a bracket (fold_lifetime_*)
        lo0, hi0 = fa[name + "_lo"][()], fa[name + "_hi"][()]
        lo1, hi1 = fb[name + "_lo"][()], fb[name + "_hi"][()]
        for i in np.flatnonzero(both):
            line = f"  [{i}] {a[i]:.6g} [{lo0[i]:.6g}, {hi0[i]:.6g}] -> {b[i]:.6g} [{lo1[i]:.6g}, {hi1[i]:.6g}]"
            if name + "_err" in fb:
                e = fb[name + "_err"][()][i]
                line += f" +- {e:.3g}; |d|/err {d[i] / e:.3g}"
                line += "; old inside new +- err" if abs(a[i] - b[i]) <= e else "; old OUTSIDE new +- err"
            else:
                w = hi0[i] - lo0[i]
                line += f"; |d|/old bracket width {d[i] / w:.3g}"
            out.append(line)
    if name == "stick_r_mean" and "stick_r_min" in fa:
        w = fa["stick_r_max"][()] - fa["stick_r_min"][()]
        ok = both & (w > 0)
        if ok.any():
            r = d[ok] / w[ok]
            out.append(f"  against the old window's spread (stick_r_max - stick_r_min): max {r.max():.3g}, "
                       f"{int((r > 1).sum())} of {r.size} above 1")
    if name.startswith("critical_") and "_" not in name[len("critical_"):]:
        fold = "fold_" + name[len("critical_"):]
        if fold + "_err" in fb:
            c, f, e = b, fb[fold][()], fb[fold + "_err"][()]
            ok = np.isfinite(c) & np.isfinite(f) & np.isfinite(e)
            if ok.any():
                above = int((c[ok] > f[ok] + e[ok]).sum())
                out.append(f"  new {name} above new {fold} + {fold}_err: {above} of {int(ok.sum())}")
    if name == "basin_fraction" and "basin_fraction_err" in fa:
        e = np.hypot(fa["basin_fraction_err"][()], fb["basin_fraction_err"][()])
        ok = both & (e > 0)
        if ok.any():
            r = d[ok] / e[ok]
            out.append(f"  against hypot(old err, new err): max {r.max():.3g}, "
                       f"{int((r > 2).sum())} of {r.size} above 2")
    return out


def enum_lines(path, ds_a, ds_b, a, b):
    names_a, names_b = enum_names(ds_a) or {}, enum_names(ds_b) or {}
    diff = a != b
    n = int(diff.sum())
    out = [f"{path}: {n} of {a.size} differ"]
    pairs = {}
    for x, y in zip(a[diff].ravel(), b[diff].ravel()):
        k = (names_a.get(int(x), int(x)), names_b.get(int(y), int(y)))
        pairs[k] = pairs.get(k, 0) + 1
    for (x, y), c in sorted(pairs.items(), key=lambda kv: -kv[1]):
        out.append(f"  {x} -> {y}: {c}")
    if path.rsplit("/", 1)[-1].endswith(LABELLED) and n:
        for idx in list(zip(*np.nonzero(diff)))[:40]:
            out.append(f"  cell {coords(ds_b, idx)}: {names_a.get(int(a[idx]), a[idx])} -> "
                       f"{names_b.get(int(b[idx]), b[idx])}")
    return out


def attr_lines(path, ga, gb):
    out = []
    for k in sorted(set(ga.attrs) | set(gb.attrs)):
        if k in SKIP_ATTRS:
            continue
        where = f"{path}@{k}"
        if k not in ga.attrs or k not in gb.attrs:
            out.append(f"{where}: only in {'new' if k not in ga.attrs else 'old'}")
            continue
        x, y = ga.attrs[k], gb.attrs[k]
        xa, ya = np.asarray(x), np.asarray(y)
        if xa.shape == ya.shape and xa.dtype == ya.dtype and (
                np.array_equal(xa, ya, equal_nan=xa.dtype.kind == "f")):
            continue
        if k == "record":
            la, lb = text(x).splitlines(), text(y).splitlines()
            keys = [l.split("=")[0].strip() for l in sorted(set(la) ^ set(lb)) if "=" in l]
            out.append(f"{where}: lines differ for {', '.join(sorted(set(keys)))}")
        elif xa.dtype.kind in "fiu" and xa.size == 1 and ya.size == 1:
            xv, yv = float(xa), float(ya)
            rel = abs(yv - xv) / abs(xv) if xv else float("inf")
            out.append(f"{where}: {x} -> {y} (rel {rel:.3g})")
        elif xa.dtype.kind in "fiu" and xa.shape == ya.shape:
            out.append(f"{where}: max |d| {np.max(np.abs(ya.astype(float) - xa.astype(float))):.3g}")
        else:
            out.append(f"{where}: {short(x, 70)!r} -> {short(y, 70)!r}")
    return out


def walk(fa, fb, out):
    for p, x, y in pairs(fa, fb):
        if x is None or y is None:
            out.append(f"{p}: only in {'new' if x is None else 'old'}")
            continue
        out += attr_lines(p, x, y)
        if isinstance(x, h5py.Dataset) and isinstance(y, h5py.Dataset):
            if x.shape != y.shape:
                out.append(f"{p}: shape {x.shape} -> {y.shape}")
            elif x.dtype != y.dtype and enum_names(x) is None:
                out.append(f"{p}: type {x.dtype} -> {y.dtype}")
            else:
                a, b = x[()], y[()]
                if x.dtype.kind == "O" or x.dtype.kind in "SU":
                    a, b = np.vectorize(text)(a), np.vectorize(text)(b)
                    diff = a != b
                    if diff.any():
                        out.append(f"{p}: {int(diff.sum())} of {a.size} differ")
                        for idx in list(zip(*np.nonzero(diff)))[:10]:
                            out.append(f"  {coords(y, idx)}: {short(a[idx])!r} -> {short(b[idx])!r}")
                elif enum_names(x) is not None or enum_names(y) is not None:
                    if (a != b).any():
                        out += enum_lines(p, x, y, a, b)
                elif x.dtype.kind in "fiu":
                    a64, b64 = a.astype(float), b.astype(float)
                    if ((a64 != b64) & ~(np.isnan(a64) & np.isnan(b64))).any():
                        out.append(numeric_line(p, a64, b64))
                        if p.count("/") == 1:
                            out += accuracy(p, fa, fb)
                elif not np.array_equal(a, b):
                    out.append(f"{p}: values differ")


NAME_CLASSES = ("added", "removed", "attribute value changed", "type or shape changed",
                "values changed")


def name_classes(fa, fb):
    """Each difference as (class, name): the class one of NAME_CLASSES, record digits as N."""
    def put(cls, name, kind="dataset"):
        out.add((cls, re.sub(r"_\d+(?=/|@|$)", "_N", name), kind))
    out = set()
    for p, x, y in pairs(fa, fb):
        if x is None or y is None:
            kind = "group" if isinstance(x or y, h5py.Group) else "dataset"
            put("added" if x is None else "removed", p, kind)
            continue
        for k in sorted((set(x.attrs) | set(y.attrs)) - SKIP_ATTRS):
            if k not in x.attrs or k not in y.attrs:
                put("added" if k not in x.attrs else "removed", f"{p}@{k}", "attribute")
            elif not same_values(x.attrs[k], y.attrs[k]):
                put("attribute value changed", f"{p}@{k}", "attribute")
        if isinstance(x, h5py.Dataset) and isinstance(y, h5py.Dataset):
            if x.shape != y.shape or (x.dtype != y.dtype and enum_names(x) is None):
                put("type or shape changed", p)
            elif not same_values(x[()].astype(y.dtype) if enum_names(x) else x[()], y[()]):
                put("values changed", p)
    return out


def spec_list(specs, compared, kinds):
    """The specs, or "every scan" / "every atlas" (by `kinds`, spec -> kind), or "all N" /
    "all N but ..." where that is shorter."""
    for kind in ("scan", "atlas"):
        every = [n for n in compared if kinds[n] == kind]
        if len(every) > 1 and sorted(specs) == every:
            return f"every {kind} ({len(every)})"
    rest = [n for n in compared if n not in specs]
    if len(rest) < len(specs):
        return f"all {len(compared)}" + (f" but {', '.join(rest)}" if rest else "")
    return ", ".join(specs)


def name_tables(old_dir, new_dir, specs):
    """The --names tables: each class's names, each with the specs where it differs."""
    where, alone, kinds = {}, [], {}
    for n in specs:
        pa, pb = os.path.join(old_dir, n + ".h5"), os.path.join(new_dir, n + ".h5")
        if not (os.path.exists(pa) and os.path.exists(pb)):
            alone.append(f"`{n}` ({'new' if os.path.exists(pb) else 'old'} only)")
            continue
        with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
            kinds[n] = "atlas" if "atlas" in text(fb.attrs.get("schema", "")) else "scan"
            for key in name_classes(fa, fb):
                where.setdefault(key, []).append(n)
    compared = [n for n in specs if n not in {a.split("`")[1] for a in alone}]
    both = len(compared)
    differ = {n for s in where.values() for n in s}
    equal = [n for n in compared if n not in differ]
    print(f"Specs compared: {both}; equal: {', '.join(equal) or 'none'}. "
          f"Written by one binary only: {', '.join(alone) or 'none'}.")
    for cls in NAME_CLASSES:
        rows = sorted((name, kind, s) for (c, name, kind), s in where.items() if c == cls)
        print(f"\n**{cls}**: {len(rows) or 'none'}")
        if rows:
            print("\n| name | kind | specs |\n|---|---|---|")
        for name, kind, s in rows:
            print(f"| `{name}` | {kind} | {spec_list(s, compared, kinds)} |")


def main():
    args = [a for a in sys.argv[1:] if a != "--names"]
    if len(args) < 2:
        sys.exit(__doc__)
    old_dir, new_dir, only = args[0], args[1], set(args[2:])
    if "--names" in sys.argv:
        name_tables(old_dir, new_dir, sorted(
            n[:-3] for n in set(os.listdir(old_dir)) | set(os.listdir(new_dir))
            if n.endswith(".h5") and (not only or n[:-3] in only)))
        return
    names = sorted(set(os.listdir(old_dir)) | set(os.listdir(new_dir)))
    for n in names:
        if not n.endswith(".h5") or (only and n[:-3] not in only):
            continue
        pa, pb = os.path.join(old_dir, n), os.path.join(new_dir, n)
        if not (os.path.exists(pa) and os.path.exists(pb)):
            print(f"== {n[:-3]}: only in {'new' if os.path.exists(pb) else 'old'}")
            continue
        out = []
        with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
            walk(fa, fb, out)
        print(f"== {n[:-3]}: {len(out) and sum(1 for l in out if not l.startswith('  '))} difference(s)")
        for line in out:
            print(f"  {line}")


if __name__ == "__main__":
    main()
