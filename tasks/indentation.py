"""Stage ``indentation``: the dent ellipse through the pile-up crest (paper Figs. 8-10)."""

from __future__ import annotations

import xarray as xr

from peenflow.methods import dent_ellipse

from ._common import peening_task
from .outputs import Output, Outputs
from .single_impact import OUTPUTS as IMPACT

OUTPUTS = Outputs(
    "indentation",
    dent_centre_x_m=Output((), "m", "dent ellipse centre x"),
    dent_centre_y_m=Output((), "m", "dent ellipse centre y"),
    impact_x_m=Output((), "m", "impact point x"),
    impact_y_m=Output((), "m", "impact point y"),
    dent_semi_axis_along_m=Output((), "m", "dent ellipse semi-axis along the impingement direction"),
    dent_semi_axis_across_m=Output((), "m", "dent ellipse semi-axis across it"),
    dent_depth_m=Output((), "m", "dent depth below the original surface"),
    pileup_height_m=Output((), "m", "pile-up crest height above the original surface"),
    dent_area_m2=Output((), "m2", "dent ellipse area"),
    crest_x_m=Output(("crest_point",), "m", "pile-up crest point x"),
    crest_y_m=Output(("crest_point",), "m", "pile-up crest point y"),
    fit_rms_m=Output((), "m", "RMS distance of the crest points from the ellipse"),
)


@peening_task(version="1")
def indentation(impact: xr.Dataset, *, rim: str = "crest", angle_deg: float | None = None) -> xr.Dataset:
    """Dent ellipse of ``impact`` (``angle_deg`` names the point of a swept stage)."""
    x = impact.x_node_full.values
    y = impact.y_node_full.values
    e = dent_ellipse(x, y, IMPACT.surface_uz_m.read(impact), (0.0, 0.0), rim=rim,
                     max_radius=0.45 * float(min(x[-1] - x[0], y[-1] - y[0])))
    return OUTPUTS.dataset(
        {"dent_centre_x_m": e.centre_x, "dent_centre_y_m": e.centre_y, "impact_x_m": e.impact_x,
         "impact_y_m": e.impact_y, "dent_semi_axis_along_m": e.semi_axis_along,
         "dent_semi_axis_across_m": e.semi_axis_across, "dent_depth_m": e.depth, "pileup_height_m": e.pileup_height,
         "dent_area_m2": e.area, "crest_x_m": e.crest_x, "crest_y_m": e.crest_y, "fit_rms_m": e.fit_rms},
        attrs={"rim": rim},
    )
