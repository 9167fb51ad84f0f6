#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = ["h5py", "numpy"]
# ///
"""Compare two HDF5 files written by squeal: every group, dataset and attribute, with types,
shapes and values bit for bit (NaN equals NaN). Provenance attributes (software version, git
revision, creation time) are reported apart and do not count as differences. Exits 1 when
anything else differs. Used by scripts/tools/same-results.sh."""
import argparse
import sys

import h5py
import numpy as np

PROVENANCE = {"software_version", "git_revision", "created", "version", "squeal_version",
              "history", "date_created", "creation_time"}


def same_values(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.names:
        return all(same_values(a[n], b[n]) for n in a.dtype.names)
    if a.dtype.kind in "fc":
        # Bit for bit, or equal as numbers with NaN = NaN (so -0.0 = 0.0 and NaN payloads pass).
        return a.tobytes() == b.tobytes() or bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def describe(v):
    a = np.asarray(v)
    if a.size <= 4:
        return repr(v)
    return f"{a.dtype} {a.shape}"


def deref(f, k, v):
    """Dimension-scale references by the names they point to (references compare by identity)."""
    if k == "DIMENSION_LIST":
        return [[f[r].name for r in refs] for refs in v]
    if k == "REFERENCE_LIST":
        return [(f[r[0]].name, int(r[1])) for r in v]
    return None


def attrs(obj, path, out, prov):
    keys = set(obj[0].attrs) | set(obj[1].attrs)
    for k in sorted(keys):
        where = f"{path}@{k}"
        if k not in obj[0].attrs or k not in obj[1].attrs:
            side = "new" if k not in obj[0].attrs else "old"
            out.append(f"{where}: only in {side}")
            continue
        a, b = obj[0].attrs[k], obj[1].attrs[k]
        ra, rb = deref(obj[0].file, k, a), deref(obj[1].file, k, b)
        if ra is not None or rb is not None:
            if ra != rb:
                out.append(f"{where}: {ra} -> {rb}")
            continue
        if same_values(a, b):
            continue
        (prov if k in PROVENANCE else out).append(f"{where}: {describe(a)} -> {describe(b)}")


def pairs(a, b, path="/"):
    """Both files' objects in step, depth first: `(path, x, y)`, `x` or `y` None where the
    object is in one file only; a group's members are visited where it is a group in both."""
    yield path, a, b
    if not (isinstance(a, h5py.Group) and isinstance(b, h5py.Group)):
        return
    for k in sorted(set(a) | set(b)):
        p = f"{path.rstrip('/')}/{k}"
        if k not in a or k not in b:
            yield p, a.get(k), b.get(k)
        else:
            yield from pairs(a[k], b[k], p)


def walk(a, b, path, out, prov):
    for p, x, y in pairs(a, b, path):
        if x is None or y is None:
            out.append(f"{p}: only in {'new' if x is None else 'old'}")
            continue
        if isinstance(x, h5py.Dataset) != isinstance(y, h5py.Dataset):
            out.append(f"{p}: a dataset in one file, a group in the other")
            continue
        if isinstance(x, h5py.Dataset):
            if x.dtype != y.dtype or x.shape != y.shape:
                out.append(f"{p}: {x.dtype} {x.shape} -> {y.dtype} {y.shape}")
            elif not same_values(x[()], y[()]):
                xv, yv = np.asarray(x[()]), np.asarray(y[()])
                diff = xv != yv
                if xv.dtype.kind in "fc":
                    diff &= ~(np.isnan(xv) & np.isnan(yv))
                n = int(np.sum(diff)) if np.asarray(diff).dtype == bool else -1
                out.append(f"{p}: values differ ({n} of {x.size} elements)")
        attrs((x, y), p, out, prov)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--label", default=None)
    args = ap.parse_args()
    out, prov = [], []
    with h5py.File(args.old, "r") as a, h5py.File(args.new, "r") as b:
        walk(a, b, "/", out, prov)
    label = args.label or args.new
    if out:
        print(f"  {label}: {len(out)} difference(s)")
        for line in out[:30]:
            print(f"    {line}")
        if len(out) > 30:
            print(f"    ... and {len(out) - 30} more")
    else:
        print(f"  {label}: equal ({len(prov)} provenance attribute(s) differ)")
    return 1 if out else 0


if __name__ == "__main__":
    sys.exit(main())
