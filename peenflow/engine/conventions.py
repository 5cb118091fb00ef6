"""CF conventions for every stored result, applied in one place (the runner, before writing).

What every result file gets, whatever task made it:

* global attributes ``Conventions = "CF-1.11"``, ``title``, ``history`` and
  ``source`` (the peenflow version and the task's code fingerprint);
* every dimension a coordinate variable: a dimension the task left bare gets
  integer positions (``units = "1"``);
* the point's sweep values (e.g. ``angle_deg = 45``) as *length-1 dimension
  coordinates*, so ``xr.open_mfdataset(files, combine="by_coords")`` assembles
  a sweep from its point files (a 0-d scalar coordinate is not enough: xarray
  orders files only by dimension coordinates);
* text variables written as fixed-width character arrays (CF has no
  variable-length strings before 1.12, and checkers refuse them).

Per-variable ``units``/``long_name``/``standard_name`` are the task's to
give; :func:`cf_problems` lists what a Dataset still lacks, so tests can hold
every task to it without the external checker.

Reading back for a task, :func:`squeeze_point` turns the length-1 sweep
dimensions into 0-d coordinates again, so a task sees the arrays it would
have seen without them.
"""

from __future__ import annotations

import re
from typing import Mapping

import numpy as np
import xarray as xr

from .content import DESCRIPTIVE_ATTRS  # noqa: F401  (left out of content hashes)

CONVENTIONS = "CF-1.11"


def _index_attrs(dim: str) -> dict:
    return {"units": "1", "long_name": f"{dim.replace('_', ' ')} index (position along the dimension)"}


def conform(ds: xr.Dataset, *, sweep: Mapping, sweep_attrs: Mapping[str, Mapping] | None = None,
            title: str, history: str, source: str) -> xr.Dataset:
    """``ds`` as it is stored: the conventions of the module docstring applied.

    ``sweep``: the point's sweep coordinates ({dim: value}); ``sweep_attrs``:
    attributes of those coordinates ({dim: {"units": ..., "long_name": ...}}).
    """
    sweep_attrs = sweep_attrs or {}
    ds = ds.copy()
    # Bare dimensions: positions as their coordinate.
    bare = [d for d in ds.dims if d not in ds.variables]
    if bare:
        ds = ds.assign_coords({d: (d, np.arange(ds.sizes[d]), _index_attrs(d)) for d in bare})
    # The point's sweep values as length-1 dimensions.  Auxiliary coordinates
    # must take the new dims too, or two points' differing values of them
    # would conflict when a sweep is assembled.
    dims = [d for d in sweep if d not in ds.dims]
    if dims:
        ds = ds.drop_vars([d for d in dims if d in ds.variables])
        loose = [k for k in ds.coords if k not in ds.dims]
        ds = ds.reset_coords(loose).expand_dims({d: [sweep[d]] for d in dims}).set_coords(loose)
    for d in sweep:
        if d in sweep_attrs:
            ds[d].attrs.update(sweep_attrs[d])
    for name, v in ds.variables.items():
        if v.dtype.kind in "OU":
            v.encoding.update({"dtype": "S1", "char_dim_name": f"{name}_strlen"})
    ds.attrs.update({"Conventions": CONVENTIONS, "title": title, "history": history, "source": source})
    return ds


def as_point(ds: xr.Dataset, coords: Mapping) -> xr.Dataset:
    """``ds`` with each sweep value of ``coords`` as a length-1 dimension (a no-op on a conformed file).

    Results stored before the conventions (sweep values only in attributes) are
    expanded here, so old and new files combine alike.
    """
    dims = {d: [v] for d, v in coords.items() if d not in ds.dims}
    if not dims:
        return ds
    ds = ds.drop_vars([d for d in dims if d in ds.variables])
    loose = [k for k in ds.coords if k not in ds.dims]
    return ds.reset_coords(loose).expand_dims(dims).set_coords(loose)


def stored_point_dims(ds: xr.Dataset) -> list[str]:
    """The sweep dimensions a stored result was written with (from its ``peenflow_point`` label,
    ``stage[dim=value,...]``)."""
    label = str(ds.attrs.get("peenflow_point", ""))
    inner = label.partition("[")[2].rstrip("]")
    return [kv.split("=", 1)[0] for kv in inner.split(",") if "=" in kv]


def retag_point(ds: xr.Dataset, coords: Mapping) -> xr.Dataset:
    """A stored result as a point with ``coords``: length-1 sweep dimensions it was written with that this
    point does not have are dropped (a result shared by two studies carries the first one's dimensions;
    what a dimension does not reach is the same result in both)."""
    stray = [d for d in stored_point_dims(ds) if d not in coords and ds.sizes.get(d) == 1]
    return ds.squeeze(stray, drop=True) if stray else ds


def squeeze_point(ds: xr.Dataset, dims) -> xr.Dataset:
    """The length-1 sweep dimensions ``dims`` as 0-d coordinates (what a task receives)."""
    present = [d for d in dims if d in ds.dims]
    return ds.squeeze(present) if present else ds


# -- checking ------------------------------------------------------------------

# A unit string CF (UDUNITS-2) accepts, for the units these results use:
# products of prefixed symbols with integer powers, "/" for one division.
_PREFIX = "(?:Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|µ|n|p|f|a)?"
_SYMBOL = "(?:m|s|g|N|Pa|J|W|K|Hz|rad|degree|degrees|%|percent|1)"
_FACTOR = rf"{_PREFIX}{_SYMBOL}(?:\^?-?\d+)?"
_UNITS = re.compile(rf"^{_FACTOR}(?:[ .]{_FACTOR})*(?:/{_FACTOR}(?:[ .]{_FACTOR})*)?$")

#: names of coordinates that measure depth below the peened surface
DEPTH_NAMES = ("depth_m", "z_edge_m", "z_cell", "z_node", "measured_depth_m")


def units_ok(units: str) -> bool:
    """True for a UDUNITS-2 unit of the kinds used here ("1" for counts and ratios)."""
    return bool(_UNITS.match(units.strip())) if units else False


def cf_problems(ds: xr.Dataset, *, sweep: Mapping | None = None) -> list[str]:
    """What ``ds`` (as read back from a result file) lacks of the conventions; [] when none.

    The rules the external checker applies that matter here, stated
    explicitly: global attributes, units valid and present, a long or standard
    name on every variable, a coordinate for every dimension, depth pointing
    down, no text that is not fixed-width, sweep values as dimensions.
    """
    out = []
    if ds.attrs.get("Conventions") != CONVENTIONS:
        out.append(f"global Conventions = {ds.attrs.get('Conventions')!r}, expected {CONVENTIONS!r}")
    for a in ("title", "history", "source"):
        if not str(ds.attrs.get(a, "")).strip():
            out.append(f"global attribute {a!r} missing")
    for name, v in ds.variables.items():
        units = v.attrs.get("units")
        if v.dtype.kind not in "OUS":
            if units is None:
                out.append(f"{name}: no units")
            elif not units_ok(str(units)):
                out.append(f"{name}: units {units!r} are not UDUNITS (counts and ratios are '1')")
        if not (v.attrs.get("long_name") or v.attrs.get("standard_name")):
            out.append(f"{name}: no long_name or standard_name")
        if name in DEPTH_NAMES and name in ds.coords and v.attrs.get("positive") != "down":
            out.append(f"{name}: depth coordinate without positive = 'down'")
        if name in DEPTH_NAMES and name not in ds.coords:
            out.append(f"{name}: depth is a data variable, expected a coordinate")
        if v.dtype.kind in "OU" and v.encoding.get("dtype") is str:
            out.append(f"{name}: variable-length string")
    for d in ds.dims:
        if d not in ds.coords:
            out.append(f"dimension {d!r} has no coordinate variable")
    for d in (sweep or {}):
        if d not in ds.dims:
            out.append(f"sweep value {d!r} is not a dimension coordinate")
    return out
