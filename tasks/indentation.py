"""Stage ``indentation``: the dent ellipse through the pile-up crest (paper Figs. 8-10)."""

from __future__ import annotations

import xarray as xr

from peenflow.methods import dent_ellipse

from ._common import peening_task, var


@peening_task(version="1")
def indentation(impact: xr.Dataset, *, rim: str = "crest", angle_deg: float | None = None) -> xr.Dataset:
    """Dent ellipse of ``impact`` (``angle_deg`` names the point of a swept stage)."""
    x = impact.x_node_full.values
    y = impact.y_node_full.values
    e = dent_ellipse(x, y, impact.surface_uz_m.values, (0.0, 0.0), rim=rim,
                     max_radius=0.45 * float(min(x[-1] - x[0], y[-1] - y[0])))
    return xr.Dataset(
        {
            "dent_centre_x_m": var(e.centre_x, (), "m", "dent ellipse centre x"),
            "dent_centre_y_m": var(e.centre_y, (), "m", "dent ellipse centre y"),
            "impact_x_m": var(e.impact_x, (), "m", "impact point x"), "impact_y_m": var(e.impact_y, (), "m", "impact point y"),
            "dent_semi_axis_along_m": var(e.semi_axis_along, (), "m",
                                          "dent ellipse semi-axis along the impingement direction"),
            "dent_semi_axis_across_m": var(e.semi_axis_across, (), "m", "dent ellipse semi-axis across it"),
            "dent_depth_m": var(e.depth, (), "m", "dent depth below the original surface"),
            "pileup_height_m": var(e.pileup_height, (), "m", "pile-up crest height above the original surface"),
            "dent_area_m2": var(e.area, (), "m2", "dent ellipse area"),
            "crest_x_m": var(e.crest_x, ("crest_point",), "m", "pile-up crest point x"),
            "crest_y_m": var(e.crest_y, ("crest_point",), "m", "pile-up crest point y"),
            "fit_rms_m": var(e.fit_rms, (), "m", "RMS distance of the crest points from the ellipse"),
        },
        attrs={"rim": rim},
    )
