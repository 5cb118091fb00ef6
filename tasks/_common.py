"""Shared by the stage modules: the task decorator they use and the CF helpers of their results.

Results are SI; ``MM`` and ``MPA`` are for the edges that show mm and MPa
(headline, plots, messages).

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


def var(values, dims=(), units: str = "1", long_name: str = "", **attrs) -> xr.Variable:
    """An ``xr.Variable`` with CF ``units`` and ``long_name`` (both stored on every variable).

    ``units``: a UDUNITS-2 string; counts, ratios and flags are ``"1"``.
    ``long_name`` is required: a stored number must say what it is.  Extra
    ``attrs`` (``standard_name``, ``positive``, ``flag_values``...) are kept.
    Text values need no units (but prefer :func:`labels` for named entries).
    """
    values = np.asarray(values)
    if not long_name:
        raise ValueError(f"var(): every stored variable needs a long_name (units {units!r}, dims {dims})")
    a = {"long_name": long_name}
    if values.dtype.kind not in "OUS":
        a["units"] = units or "1"
    a.update(attrs)
    return xr.Variable(dims, values, attrs=a)


def depth(values, dim: str, long_name: str) -> xr.Variable:
    """A depth below the peened surface (m), as a CF vertical coordinate (``positive = "down"``)."""
    return var(values, (dim,), "m", long_name, standard_name="depth", positive="down")


def labels(names, dim: str, long_name: str) -> xr.Variable:
    """A dimension of named entries (stress components, vector axes) as a CF flag coordinate.

    CF coordinate variables are numeric, so the entries are 0, 1, ... with
    their names in ``flag_meanings`` (``ds.component.attrs["flag_meanings"].split()``).
    """
    names = list(names)
    return var(np.arange(len(names)), (dim,), "1", long_name, flag_values=np.arange(len(names)),
               flag_meanings=" ".join(names))


#: CF attributes of the sweep coordinates the pipeline uses (engine Graph.coord_attrs)
SWEEP_COORDS = {
    "angle_deg": {"units": "degree", "long_name": "impingement angle (90 = normal to the surface)"},
    "velocity_m_s": {"units": "m s-1", "long_name": "shot velocity"},
    "sequence": {"units": "1", "long_name": "random shot sequence number"},
}

#: long name of the six stress components' dimension (Voigt order)
COMPONENT_LONG_NAME = "stress component (Voigt order xx, yy, zz, yz, xz, xy)"
