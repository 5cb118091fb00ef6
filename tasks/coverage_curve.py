"""Stage ``coverage_curve``: coverage vs shot number on the REV, N_f and N_c (paper §3.2.2, eq. 5).

The dent ellipse of a single impact (stage ``indentation``) is stamped at
random landing points over the whole peening surface -- drawn by the same
shot-stream generator the REV runs use (eqs. 2-3), with their own seeds --
and the fraction of the measuring region's grid
nodes inside any dent is the coverage.  Eq. (5) is fitted to all
sequences; N_f is the shot number of 98 % coverage and N_c the one of the
specified coverage (200 % = 2 N_f).  The closed form for uniform landings,
100 (1 - (1 - A_dent/A_peen)^N), is stored beside it as a check.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from peenflow.methods import (DentEllipse, expected_coverage_uniform, fit_avrami, measuring_grid,
                              shot_stream)
from peenflow.methods.coverage import coverage_curves

from ._common import peening_task, var
from .indentation import OUTPUTS as DENT
from .outputs import Output, Outputs
from .params import CoverageParams
from .rev_size import OUTPUTS as REV

OUTPUTS = Outputs(
    "coverage_curve",
    coverage_curve_percent=Output(("sequence", "shots"), "%", "Monte-Carlo coverage of the measuring region"),
    coverage_mean_percent=Output(("shots",), "%", "Monte-Carlo coverage, mean over sequences"),
    avrami_coverage_percent=Output(("shots",), "%", "coverage by the eq. (5) fit"),
    uniform_closed_form_percent=Output(("shots",), "%",
                                       "closed form for uniform landings, 100 (1 - (1 - A_dent/A_peen)^N)"),
    avrami_rate=Output((), "1", "A of eq. (5), per shot"),
    avrami_residual_rms_percent=Output((), "%", "RMS residual of the eq. (5) fit"),
    full_coverage_shots=Output((), "1", "N_f: shots for full coverage (attribute full_coverage_percent)"),
    coverage_shots=Output(("coverage_percent",), "1", "N_c: shots for each coverage level"),
    coverage_shots_rounded=Output(("coverage_percent",), "1", "N_c rounded up to whole shots"),
    dent_area_m2=Output((), "m2", "dent ellipse area"),
    peening_area_m2=Output((), "m2", "area the shots land on (REV top surface)"),
)


def dent_from_dataset(ds: xr.Dataset) -> DentEllipse:
    """The dent ellipse of an ``indentation`` result."""
    return DentEllipse(
        centre_x=DENT.dent_centre_x_m.read(ds), centre_y=DENT.dent_centre_y_m.read(ds),
        impact_x=DENT.impact_x_m.read(ds), impact_y=DENT.impact_y_m.read(ds),
        semi_axis_along=DENT.dent_semi_axis_along_m.read(ds),
        semi_axis_across=DENT.dent_semi_axis_across_m.read(ds),
        depth=DENT.dent_depth_m.read(ds), pileup_height=DENT.pileup_height_m.read(ds),
    )


@peening_task(version="1")
def coverage_curve(dent: xr.Dataset, rev: xr.Dataset, *, angle_deg: float, coverage_levels_percent: tuple,
                   settings: CoverageParams) -> xr.Dataset:
    """Coverage of the ``rev`` result's measuring region by ``dent``'s ellipse, N_f, and N_c for each of
    ``coverage_levels_percent`` (%, ascending; module docstring)."""
    c = settings
    grid_points, max_shots, shot_counts, sequences = c.grid_points, c.max_shots, c.shot_counts, c.sequences
    full_coverage_percent = c.full_coverage_percent
    ellipse = dent_from_dataset(dent)
    side = REV.rev_side_m.read(rev)
    measure = REV.measure_side_m.read(rev)
    half = 0.5 * side
    region = (-0.5 * measure, 0.5 * measure, -0.5 * measure, 0.5 * measure)
    gx, gy = measuring_grid(region, grid_points)
    q = ellipse.area / side ** 2
    if q >= 1.0:  # one shot covers the whole REV: coverage has no curve, eq. (5) no rate
        raise ValueError(
            f"the REV's top surface ({side * 1e3:.4g} mm square, {side ** 2 * 1e6:.4g} mm2) is smaller than one dent "
            f"({ellipse.area * 1e6:.4g} mm2): the REV holds less than one dent, so its coverage cannot grow shot by "
            "shot. What to change: a larger target.rev_size_mm (its validated range: at least 1 D and 10 elements)")
    if shot_counts:
        counts = np.asarray(sorted(shot_counts), dtype=int)
    else:
        # enough shots for ~99.9 % expected coverage, on a geometric ladder
        n_max = max_shots or int(math.ceil(-math.log(1e-3) / -math.log1p(-q)))
        counts = np.unique(np.geomspace(1, n_max, 40).astype(int))
    n_max = int(counts.max())
    landings = [shot_stream(n_max, c.shot_radius_m, half, half, angle_deg, 1.0, int(s)).landing
                for s in c.seeds[:sequences]]
    cov = coverage_curves(landings, ellipse, gx, gy, counts)
    fit = fit_avrami(counts, cov, full_coverage_percent)
    n_f = fit.full_coverage_shots
    levels = np.asarray(coverage_levels_percent, dtype=float)
    n_c = np.array([fit.shots_for_coverage(c) for c in levels])
    return OUTPUTS.dataset(
        {"coverage_curve_percent": cov, "coverage_mean_percent": cov.mean(axis=0),
         "avrami_coverage_percent": fit.coverage_at(counts),
         "uniform_closed_form_percent": expected_coverage_uniform(counts, ellipse.area, side ** 2),
         "avrami_rate": fit.rate, "avrami_residual_rms_percent": fit.residual_rms, "full_coverage_shots": n_f,
         "coverage_shots": n_c, "coverage_shots_rounded": np.ceil(n_c).astype(int), "dent_area_m2": ellipse.area,
         "peening_area_m2": side ** 2},
        coords={"sequence": var(np.arange(len(landings)), ("sequence",), "1", "random landing sequence number"),
                "shots": var(counts, ("shots",), "1", "number of shots N"),
                "coverage_percent": var(levels, ("coverage_percent",), "%", "coverage level")},
        attrs={"full_coverage_percent": full_coverage_percent,
               "grid_points": grid_points},
    )
