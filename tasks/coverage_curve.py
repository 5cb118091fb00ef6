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

from ._common import peening_task, scalar, var
from .params import CoverageParams


def dent_from_dataset(ds: xr.Dataset) -> DentEllipse:
    return DentEllipse(
        centre_x=scalar(ds, "dent_centre_x_m"), centre_y=scalar(ds, "dent_centre_y_m"),
        impact_x=scalar(ds, "impact_x_m"), impact_y=scalar(ds, "impact_y_m"),
        semi_axis_along=scalar(ds, "dent_semi_axis_along_m"),
        semi_axis_across=scalar(ds, "dent_semi_axis_across_m"),
        depth=scalar(ds, "dent_depth_m"), pileup_height=scalar(ds, "pileup_height_m"),
    )


@peening_task(version="1")
def coverage_curve(dent: xr.Dataset, rev: xr.Dataset, *, angle_deg: float, coverage_percent: float,
                   settings: CoverageParams) -> xr.Dataset:
    """Coverage of the ``rev`` result's measuring region by ``dent``'s ellipse, N_f and
    N_c for ``coverage_percent`` (module docstring)."""
    c = settings
    grid_points, max_shots, shot_counts, sequences = c.grid_points, c.max_shots, c.shot_counts, c.sequences
    full_coverage_percent = c.full_coverage_percent
    ellipse = dent_from_dataset(dent)
    side = scalar(rev, "rev_side_m")
    measure = scalar(rev, "measure_side_m")
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
    n_c = fit.shots_for_coverage(coverage_percent)
    return xr.Dataset(
        {
            "coverage_percent": var(cov, ("sequence", "shots"), "%", "Monte-Carlo coverage of the measuring region"),
            "coverage_mean_percent": var(cov.mean(axis=0), ("shots",), "%", "Monte-Carlo coverage, mean over sequences"),
            "avrami_coverage_percent": var(fit.coverage_at(counts), ("shots",), "%", "coverage by the eq. (5) fit"),
            "uniform_closed_form_percent": var(expected_coverage_uniform(counts, ellipse.area, side ** 2),
                                               ("shots",), "%", "closed form for uniform landings, 100 (1 - (1 - A_dent/A_peen)^N)"),
            "avrami_rate": var(fit.rate, (), "1", "A of eq. (5), per shot"),
            "avrami_residual_rms_percent": var(fit.residual_rms, (), "%", "RMS residual of the eq. (5) fit"),
            "full_coverage_shots": var(n_f, (), "1", f"N_f: shots for {full_coverage_percent:g} % coverage"),
            "coverage_shots": var(n_c, (), "1", f"N_c: shots for {coverage_percent:g} % coverage"),
            "coverage_shots_rounded": var(int(math.ceil(n_c)), (), "1", "N_c rounded up to whole shots"),
            "dent_area_m2": var(ellipse.area, (), "m2", "dent ellipse area"),
            "peening_area_m2": var(side ** 2, (), "m2", "area the shots land on (REV top surface)"),
        },
        coords={"sequence": var(np.arange(len(landings)), ("sequence",), "1", "random landing sequence number"),
                "shots": var(counts, ("shots",), "1", "number of shots N")},
        attrs={"target_coverage_percent": coverage_percent, "full_coverage_percent": full_coverage_percent,
               "grid_points": grid_points},
    )
