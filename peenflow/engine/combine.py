"""Combining the results of a sweep into one Dataset along the sweep's dims."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from .content import PROVENANCE_PREFIX


def strip_provenance(ds: xr.Dataset) -> xr.Dataset:
    ds = ds.copy()
    ds.attrs = {k: v for k, v in ds.attrs.items() if not k.startswith(PROVENANCE_PREFIX)}
    return ds


def combine_points(datasets: Sequence[xr.Dataset], coords: Sequence[Mapping], dims: Sequence[str]) -> xr.Dataset:
    """Stack point Datasets along ``dims`` (each point contributes one coordinate value per dim)."""
    if not datasets:
        raise ValueError("nothing to combine")
    dims = list(dims)
    if not dims:
        if len(datasets) != 1:
            raise ValueError("several points but no dims to combine them along")
        return datasets[0]
    datasets = _index_ragged_dims(datasets)
    parts, extra = [], set()
    for ds, c in zip(datasets, coords):
        ds = strip_provenance(ds)
        # non-index coordinates may differ between points: carry them as variables
        loose = [k for k in ds.coords if k not in ds.indexes]
        extra.update(loose)
        parts.append(ds.reset_coords(loose).expand_dims({d: [c[d]] for d in dims}))
    # Points occupy disjoint coordinates along the sweep dims: an outer merge puts
    # each in its place (NaN where a point is missing or a ragged dim is shorter).
    out = xr.merge(parts, join="outer", compat="no_conflicts", combine_attrs="drop_conflicts")
    return out.set_coords(sorted(k for k in extra if k in out))


def _index_ragged_dims(datasets: Sequence[xr.Dataset]) -> list[xr.Dataset]:
    """Give dims without an index, whose length differs between points, integer positions.

    A point's own dims may be ragged across a sweep (e.g. a search that needed 7
    runs at one angle and 8 at another); indexed by position they combine
    with NaN padding instead of failing to align.
    """
    sizes: dict[str, set] = {}
    for ds in datasets:
        for d, n in ds.sizes.items():
            if d not in ds.indexes:
                sizes.setdefault(d, set()).add(n)
    ragged = [d for d, ns in sizes.items() if len(ns) > 1]
    if not ragged:
        return list(datasets)
    return [ds.assign_coords({d: np.arange(ds.sizes[d]) for d in ragged if d in ds.dims and d not in ds.indexes})
            for ds in datasets]
