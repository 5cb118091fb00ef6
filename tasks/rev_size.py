"""Stage ``rev_size``: the representative elementary volume (paper §3.1, §4.1).

Top surface: a square of side 3 d_min with the d_min x d_min measuring region
at its centre, d_min the largest over the angles searched (the paper sizes
one strip REV from its 90° and 45° extremes).  The paper's fixed strip REV
(6D x 6D, measuring 2D x 2D) and explicit sizes are the other rules.
Thickness: given (the strip's, or the part's / a chosen REV thickness), or
from the single-impact convergence check of ``rev_thickness``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._common import peening_task
from .dmin import OUTPUTS as DMIN
from .outputs import Output, Outputs
from .params import RevParams
from .rev_thickness import OUTPUTS as THICKNESS

OUTPUTS = Outputs(
    "rev_size",
    rev_side_m=Output((), "m", "REV top-surface side"),
    measure_side_m=Output((), "m", "central measuring-region side"),
    thickness_m=Output((), "m", "REV thickness"),
    d_min_m=Output((), "m", "d_min used (NaN when not from a search)"),
)


@peening_task(version="2")
def rev_size(dmin: xr.Dataset | None = None, thickness: xr.Dataset | None = None, *, rev: RevParams) -> xr.Dataset:
    """``thickness``: a rev_thickness result; it replaces ``rev.thickness_m`` when given."""
    thickness_m = rev.thickness_m if thickness is None else THICKNESS.thickness_m.read(thickness)
    if rev.rule == "dmin" and dmin is None:
        raise ValueError("rule 'dmin' needs the d_min search upstream")
    d_min = float("nan") if dmin is None else float(np.nanmax(DMIN.d_min_m.read(dmin)))
    geometry = rev.geometry(None if dmin is None else d_min)
    side, measure = geometry.side, geometry.measuring_side
    return OUTPUTS.dataset({"rev_side_m": side, "measure_side_m": measure, "thickness_m": thickness_m,
                            "d_min_m": d_min}, attrs={"rule": rev.rule})
