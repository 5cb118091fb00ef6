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

from ._common import peening_task, var


@peening_task(version="2")
def rev_size(dmin: xr.Dataset | None = None, thickness: xr.Dataset | None = None, *, rule: str,
             thickness_m: float, shot_diameter_m: float, side_m: float | None = None,
             measure_side_m: float | None = None) -> xr.Dataset:
    """``thickness``: a rev_thickness result; it replaces ``thickness_m`` when given."""
    if thickness is not None:
        thickness_m = float(thickness.thickness_m)
    d_min = float("nan")
    if rule == "dmin":
        if dmin is None:
            raise ValueError("rule 'dmin' needs the d_min search upstream")
        d_min = float(np.nanmax(np.asarray(dmin.d_min_m.values)))
        side, measure = 3.0 * d_min, d_min
    elif rule == "paper":
        side, measure = 6.0 * shot_diameter_m, 2.0 * shot_diameter_m
    elif rule == "explicit":
        side = side_m
        measure = measure_side_m if measure_side_m is not None else side_m / 3.0
    else:
        raise ValueError(f"unknown REV rule {rule!r}")
    if side_m is not None and rule != "explicit":
        side = side_m
    if measure_side_m is not None:
        measure = measure_side_m
    if not 0 < measure <= side:  # == side: the whole face (periodic lateral faces have no edge to avoid)
        raise ValueError(f"measuring region {measure:.4g} m must be > 0 and at most the REV side {side:.4g} m")
    return xr.Dataset(
        {
            "rev_side_m": var(side, (), "m", "REV top-surface side"),
            "measure_side_m": var(measure, (), "m", "central measuring-region side"),
            "thickness_m": var(thickness_m, (), "m", "REV thickness"),
            "d_min_m": var(d_min, (), "m", "d_min used (NaN when not from a search)"),
        },
        attrs={"rule": rule},
    )
