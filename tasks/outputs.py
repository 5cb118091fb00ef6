"""The one door out: each stage declares its outputs once, and writes and reads them through that.

A stage module declares what its result holds::

    OUTPUTS = Outputs("rev_size",
        rev_side_m=Output((), "m", "REV top-surface side"),
        d_min_m=Output((), "m", "d_min used (NaN when not from a search)"),
    )

and builds its Dataset with ``OUTPUTS.dataset({"rev_side_m": side, ...}, coords=..., attrs=...)``:
every variable gets the declared dims, CF ``units`` and ``long_name`` (a name not declared, or a
value whose rank differs from its dims, is a programming error caught on the spot).  A stage
downstream reads an upstream value through the same declaration,
``rev_size.OUTPUTS.rev_side_m.read(ds)``, which checks the variable is there with the declared
units -- instead of looking a string up in a Dataset and hoping it means what it meant.

Declarations are registered by task name (:data:`DECLARED`), so a test can hold every stored
result of a study against its stage's declaration.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import xarray as xr

from ._common import var

__all__ = ["Output", "Outputs", "DECLARED"]

#: task name -> its declared outputs
DECLARED: dict[str, "Outputs"] = {}


@dataclass(frozen=True)
class Output:
    """One declared variable: ``dims``, CF ``units`` (UDUNITS-2; "1" for counts and ratios) and
    ``long_name``; ``optional``: a result may leave it out (it depends on the study: a measured
    profile, the free part); ``attrs``: further CF attributes (``standard_name``, ``flag_meanings``)."""

    dims: tuple[str, ...]
    units: str
    long_name: str
    optional: bool = False
    attrs: Mapping = field(default_factory=dict)
    name: str = ""

    def variable(self, values, lead: tuple[str, ...] = ()) -> xr.Variable:
        """The variable of ``values``, whose dims are ``lead`` (a map's process dimensions) then the declared."""
        values = np.asarray(values)
        dims = tuple(lead) + self.dims
        if values.ndim != len(dims):
            raise ValueError(f"output {self.name!r} is declared with dims {dims}, got an array of shape "
                             f"{values.shape}")
        return var(values, dims, self.units, self.long_name, **self.attrs)

    def read(self, ds: xr.Dataset):
        """The value in an upstream result: a float for a 0-d output, else a numpy array (SI, the
        declared units)."""
        if self.name not in ds:
            raise KeyError(f"upstream result has no {self.name!r} ({self.long_name}); it has "
                           f"{sorted(ds.data_vars)}")
        v = ds[self.name]
        units = v.attrs.get("units")
        if units is not None and units != self.units:
            raise ValueError(f"upstream {self.name!r} is in {units!r}, declared {self.units!r}")
        values = np.asarray(v.values)
        return float(values.reshape(())) if not self.dims else values


class Outputs:
    """The declared outputs of one task (module docstring); attribute access gives each :class:`Output`."""

    def __init__(self, task: str, **outputs: Output):
        self.task = task
        self._outputs = {name: _named(o, name) for name, o in outputs.items()}
        DECLARED[task] = self

    def __getattr__(self, name: str) -> Output:
        try:
            return self.__dict__["_outputs"][name]
        except KeyError:
            raise AttributeError(f"{self.__dict__.get('task')!r} declares no output {name!r}") from None

    def __iter__(self):
        return iter(self._outputs.values())

    def derive(self, task: str, drop: tuple[str, ...] = (), **changes: Output) -> "Outputs":
        """The declaration of another task whose result is this one's, less ``drop``, with ``changes``."""
        kept = {n: o for n, o in self._outputs.items() if n not in drop}
        return Outputs(task, **{**kept, **changes})

    def dataset(self, values: Mapping, coords: Mapping | None = None, attrs: Mapping | None = None,
                lead: tuple[str, ...] = ()) -> xr.Dataset:
        """The result from ``{declared name: values}``; every non-optional output must be given; ``lead``:
        dimensions before every output's declared ones (a map over process dimensions, recorded in the
        attribute ``process_dims``)."""
        unknown = set(values) - set(self._outputs)
        if unknown:
            raise KeyError(f"{self.task}: outputs {sorted(unknown)} are not declared")
        missing = [n for n, o in self._outputs.items() if not o.optional and n not in values]
        if missing:
            raise KeyError(f"{self.task}: declared outputs {missing} not given")
        data = {n: self._outputs[n].variable(v, tuple(lead)) for n, v in values.items()}
        attrs = dict(attrs or {})
        if lead:
            attrs["process_dims"] = " ".join(lead)
        return xr.Dataset(data, coords=dict(coords or {}), attrs=attrs)

    def problems(self, ds: xr.Dataset, point_dims=()) -> list[str]:
        """How a stored result departs from this declaration (empty when it matches); ``point_dims``:
        the point's sweep dims, which a stored result carries as length-1 dims of every variable."""
        out = []
        point_dims = tuple(point_dims) + tuple(str(ds.attrs.get("process_dims", "")).split())
        for name in ds.data_vars:
            o = self._outputs.get(name)
            if o is None:
                out.append(f"{name}: not declared")
                continue
            if tuple(d for d in ds[name].dims if d not in point_dims) != o.dims:
                out.append(f"{name}: dims {tuple(ds[name].dims)}, declared {o.dims}")
            if ds[name].attrs.get("units") != o.units and ds[name].dtype.kind not in "OUS":
                out.append(f"{name}: units {ds[name].attrs.get('units')!r}, declared {o.units!r}")
        out += [f"{n}: declared, not in the result" for n, o in self._outputs.items()
                if not o.optional and n not in ds.data_vars]
        return out


def _named(o: Output, name: str) -> Output:
    return Output(o.dims, o.units, o.long_name, o.optional, dict(o.attrs), name)
