"""Compare every result of two stores, in SI: the before/after check of a refactoring.

    python benchmarks/compare_stores.py STORE_A STORE_B [--tolerance 1e-9] [--squeeze] [--rename OLD=NEW ...]

Results are matched by stage and point (the ``peenflow_stage`` and
``peenflow_point`` attributes every stored result has; keys may differ
between the two stores: a change in how parameters are canonicalised
changes keys but must not change numbers). Every data variable and
coordinate present in both is converted to SI from its CF ``units``
attribute (mm, um, MPa, ... -> m, Pa) and matched by its name without the
unit suffix, so ``intensity_mm`` (mm) in one store and ``intensity_m`` (m)
in the other are the same quantity. Printed per variable: the largest
difference relative to the variable's largest magnitude (0 when equal,
``nan-mismatch`` when the NaN positions differ, ``shape`` when the shapes
do); a variable in only one store is listed as such.

``--squeeze`` compares values with their length-1 dimensions dropped (a
result that gained a dimension of one value, such as a single coverage
level, holds the same numbers); ``--rename OLD=NEW`` compares store A's
variable OLD with store B's NEW (a renamed output).

Exit status 0 when every shared variable agrees within ``--tolerance``
(relative) and every result is in both stores; 1 otherwise.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from peenflow.engine import DirectoryStore

#: unit -> (factor to SI, SI unit, the name suffixes that spell it)
UNITS = {
    "mm": (1e-3, "m", ("_mm",)),
    "um": (1e-6, "m", ("_um",)),
    "m": (1.0, "m", ("_m",)),
    "MPa": (1e6, "Pa", ("_MPa",)),
    "GPa": (1e9, "Pa", ("_GPa",)),
    "Pa": (1.0, "Pa", ("_Pa",)),
    "m s-1": (1.0, "m s-1", ("_m_s",)),
    "mm2": (1e-6, "m2", ("_mm2",)),
    "m2": (1.0, "m2", ("_m2",)),
}


def si_name_and_values(name: str, var: xr.DataArray) -> tuple[str, np.ndarray]:
    """(name without its unit suffix, values in SI)."""
    values = np.asarray(var.values)
    units = var.attrs.get("units")
    if units in UNITS and values.dtype.kind in "fiu":
        factor, _, suffixes = UNITS[units]
        for suffix in suffixes:
            if name.endswith(suffix):
                return name[: -len(suffix)], values * factor
        return name, values * factor
    return name, values


def results(store: Path) -> dict[tuple[str, str], Path]:
    """{(stage, point): result file}; of several for one point, the newest."""
    found: dict[tuple[str, str], Path] = {}
    files = [path for _, _, path in DirectoryStore(store).all_results()]
    for path in sorted(files, key=lambda p: p.stat().st_mtime):
        with xr.open_dataset(path) as ds:
            label = (str(ds.attrs.get("peenflow_stage")), str(ds.attrs.get("peenflow_point")))
        found[label] = path
    return found


def variables(path: Path) -> dict[str, np.ndarray]:
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    out = {}
    for name in list(ds.data_vars) + list(ds.coords):
        base, values = si_name_and_values(name, ds[name])
        out[base] = values
    return out


def relative_difference(a: np.ndarray, b: np.ndarray) -> float | str:
    if a.shape != b.shape:
        return "shape"
    if a.dtype.kind not in "fiub" or b.dtype.kind not in "fiub":
        return 0.0 if np.array_equal(a, b) else "text"
    a, b = a.astype(float), b.astype(float)
    nan_a, nan_b = np.isnan(a), np.isnan(b)
    if not np.array_equal(nan_a, nan_b):
        return "nan-mismatch"
    ok = ~nan_a
    if not ok.any():
        return 0.0
    scale = np.max(np.abs(a[ok]))
    diff = np.max(np.abs(a[ok] - b[ok]))
    return 0.0 if diff == 0 else float(diff / scale) if scale > 0 else float("inf")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("store_a", type=Path)
    ap.add_argument("store_b", type=Path)
    ap.add_argument("--tolerance", type=float, default=1e-9, help="largest relative difference accepted")
    ap.add_argument("--squeeze", action="store_true", help="drop length-1 dimensions before comparing")
    ap.add_argument("--rename", action="append", default=[], metavar="OLD=NEW",
                    help="store A's variable OLD is store B's NEW (SI names, without unit suffix)")
    args = ap.parse_args(argv)
    renamed = dict(r.split("=", 1) for r in args.rename)
    ra, rb = results(args.store_a), results(args.store_b)
    ok = True
    worst = 0.0
    compared = 0
    for label in sorted(set(ra) | set(rb)):
        stage, point = label
        if label not in ra or label not in rb:
            print(f"{stage} {point}: only in {'A' if label in ra else 'B'}")
            ok = False
            continue
        va, vb = variables(ra[label]), variables(rb[label])
        va = {renamed.get(k, k): v for k, v in va.items() if not (k in renamed.values() and k not in renamed)}
        if args.squeeze:
            va, vb = ({k: np.squeeze(v) for k, v in d.items()} for d in (va, vb))
        print(f"{stage} {point}:")
        for name in sorted(set(va) | set(vb)):
            if name not in va or name not in vb:
                print(f"    {name:40s} only in {'A' if name in va else 'B'}")
                continue
            d = relative_difference(va[name], vb[name])
            compared += 1
            if isinstance(d, str) or d > args.tolerance:
                ok = False
            if not isinstance(d, str):
                worst = max(worst, d)
            print(f"    {name:40s} {d if isinstance(d, str) else f'{d:.3g}'}")
    print(f"results: {len(ra)} in A, {len(rb)} in B; {compared} variables compared; "
          f"largest relative difference {worst:.3g}; "
          f"{'AGREE' if ok else 'DIFFER'} (tolerance {args.tolerance:g})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
