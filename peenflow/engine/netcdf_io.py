"""All netCDF reads and writes of the engine, behind one process-wide lock.

The netCDF-C/HDF5 libraries are not thread-safe: two threads writing
different files at once crashed the interpreter (bus error) in our tests.
Compute runs in parallel threads; only file I/O is serialised here.
"""

from __future__ import annotations

import threading
from pathlib import Path

import xarray as xr

ENGINE = "netcdf4"
NETCDF_LOCK = threading.RLock()


def write_dataset(ds: xr.Dataset, path: Path) -> None:
    with NETCDF_LOCK:
        ds.to_netcdf(path, engine=ENGINE)


def read_dataset(path: Path) -> xr.Dataset:
    """The whole Dataset loaded into memory; the file is closed on return."""
    with NETCDF_LOCK:
        with xr.open_dataset(path, engine=ENGINE, cache=False) as ds:
            return ds.load()


def read_attrs(path: Path) -> dict:
    """The file's global attributes alone (no variable is read)."""
    with NETCDF_LOCK:
        with xr.open_dataset(path, engine=ENGINE, cache=False) as ds:
            return dict(ds.attrs)


def open_lazy(path: Path) -> xr.Dataset:
    """The Dataset backed by dask arrays: values are read when computed (the file stays open).

    For analysis after a run; xarray's netCDF4 backend takes its own HDF5 lock
    for every read.
    """
    return xr.open_dataset(path, engine=ENGINE, chunks={})
