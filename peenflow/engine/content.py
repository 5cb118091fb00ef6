"""Content hashes of result Datasets.

Downstream keys use the *content* of their upstream results, not the
upstream keys: an upstream rerun that produces identical data does not
invalidate anything downstream (early cut-off).  Provenance attributes
(``peenflow_*``: times, host, versions) are excluded, as are the descriptive
global attributes (``title``, ``history``, ``source``, ``Conventions``; see
conventions.py) and netCDF encoding.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np
import xarray as xr

PROVENANCE_PREFIX = "peenflow_"
#: global attributes that say where a file came from, not what it holds (CF's
#: descriptive attributes, see conventions.py): a rerun tomorrow, or another
#: study that shares the result, must hash the same
DESCRIPTIVE_ATTRS = ("Conventions", "title", "history", "source")


def _attrs_text(attrs: dict, skip: tuple = ()) -> str:
    clean = {}
    for k in sorted(attrs):
        if k.startswith(PROVENANCE_PREFIX) or k in skip:
            continue
        v = attrs[k]
        if isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, np.generic):
            v = v.item()
        clean[k] = v
    return json.dumps(clean, sort_keys=True, default=str)


def _array_bytes(values: np.ndarray) -> bytes:
    if values.dtype.kind in "OUS":
        # Strings come back from netCDF as object arrays: hash their text.
        return "\x1f".join(str(v) for v in values.ravel().tolist()).encode("utf-8")
    return np.ascontiguousarray(values).tobytes()


def dataset_content_hash(ds: xr.Dataset) -> str:
    """SHA-256 (hex, 32 chars) over variable names, dims, dtypes, values and attrs."""
    h = hashlib.sha256()
    h.update(_attrs_text(ds.attrs, DESCRIPTIVE_ATTRS).encode())
    for name in sorted(map(str, ds.variables)):
        var = ds.variables[name]
        values = np.asarray(var.values)
        kind = "str" if values.dtype.kind in "OUS" else values.dtype.str
        h.update(f"\x1e{name}|{var.dims}|{kind}|{values.shape}|".encode())
        h.update(_attrs_text(var.attrs).encode())
        h.update(_array_bytes(values))
    return h.hexdigest()[:32]
