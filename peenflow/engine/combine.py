"""Combining the results of a sweep into one Dataset along the sweep's dims."""

from __future__ import annotations

from typing import Mapping, Sequence

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
    expanded = [
        strip_provenance(ds).expand_dims({d: [c[d]] for d in dims}) for ds, c in zip(datasets, coords)
    ]
    return xr.combine_by_coords(expanded, combine_attrs="drop_conflicts", join="outer")
