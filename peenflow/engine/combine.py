"""Combining the results of a sweep into one Dataset along the sweep's dims."""

from __future__ import annotations

import json
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from .content import DESCRIPTIVE_ATTRS, PROVENANCE_PREFIX
from .conventions import as_point

#: the combined Dataset's attribute holding every point's provenance (JSON list)
POINTS_ATTR = "peenflow_points"


def strip_provenance(ds: xr.Dataset) -> xr.Dataset:
    ds = ds.copy()
    ds.attrs = {k: v for k, v in ds.attrs.items() if not k.startswith(PROVENANCE_PREFIX)}
    return ds


def _provenance(ds: xr.Dataset) -> dict:
    out = {}
    for k, v in ds.attrs.items():
        if k.startswith(PROVENANCE_PREFIX) or k in ("history", "source"):
            out[k] = v.item() if isinstance(v, np.generic) else v
    return out


def combine_points(datasets: Sequence[xr.Dataset], coords: Sequence[Mapping], dims: Sequence[str]) -> xr.Dataset:
    """Stack point Datasets along ``dims`` (each point contributes one coordinate value per dim).

    Attributes the points share are kept; those that differ (provenance: key,
    times, host) are kept per point as a JSON list in ``peenflow_points``,
    so nothing about where a value came from is lost by combining.
    """
    if not datasets:
        raise ValueError("nothing to combine")
    dims = list(dims)
    if not dims:
        if len(datasets) != 1:
            raise ValueError("several points but no dims to combine them along")
        return datasets[0]
    datasets = _index_ragged_dims([as_point(ds, {d: c[d] for d in dims}) for ds, c in zip(datasets, coords)])
    points = [_provenance(ds) for ds in datasets]
    parts = [strip_provenance(ds) for ds in datasets]
    # Points occupy disjoint coordinates along the sweep dims: an outer merge puts
    # each in its place (NaN where a point is missing or a ragged dim is shorter).
    out = xr.merge(parts, join="outer", compat="no_conflicts", combine_attrs="drop_conflicts")
    shared = {k: v for k, v in points[0].items() if all(p.get(k) == v for p in points[1:])}
    out.attrs.update(shared)
    out.attrs[POINTS_ATTR] = json.dumps(points, sort_keys=True, default=str)
    for k in DESCRIPTIVE_ATTRS:  # CF: history is a log, one line per entry
        lines = sorted({str(ds.attrs[k]) for ds in datasets if k in ds.attrs})
        if lines:
            out.attrs[k] = "\n".join(lines)
    return out


def _index_ragged_dims(datasets: Sequence[xr.Dataset]) -> list[xr.Dataset]:
    """Give dims without an index, whose length differs between points, integer positions.

    A point's own dims may be ragged across a sweep (e.g. a search that needed 7
    runs at one angle and 8 at another); indexed by position they combine
    with NaN padding instead of failing to align.  (Results written with the
    conventions already index every dim; older ones may not.)
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
