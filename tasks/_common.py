"""Shared by the stage modules: the task decorator they use and unit helpers.

Every stage declares that its results depend on the kernel and on the
paper's maths (``uses``), so an edit in ``peenflow.fe`` or
``peenflow.methods`` invalidates exactly the results computed with them --
numba's own cache would not notice an edit in another module.
"""

from __future__ import annotations

import functools

import numpy as np
import xarray as xr

from peenflow.engine import task

KERNEL_PACKAGES = ("peenflow.fe", "peenflow.methods")

#: decorator for stages that run the FE/DEM kernel or the paper's maths
peening_task = functools.partial(task, uses=KERNEL_PACKAGES)

MM = 1e-3
UM = 1e-6
MPA = 1e6


def scalar(ds: xr.Dataset, name: str) -> float:
    """A 0-d variable as a Python float (clear error if it is missing)."""
    if name not in ds:
        raise KeyError(f"upstream result has no variable {name!r}; it has {sorted(ds.data_vars)}")
    return float(np.asarray(ds[name]).reshape(()))


def var(values, dims=(), units: str = "", long_name: str = "", **attrs) -> xr.Variable:
    """An ``xr.Variable`` with ``units``/``long_name`` attrs (netCDF-friendly)."""
    a = {"units": units} if units else {}
    if long_name:
        a["long_name"] = long_name
    a.update(attrs)
    return xr.Variable(dims, np.asarray(values), attrs=a)
