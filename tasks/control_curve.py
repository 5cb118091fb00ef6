"""Stage ``control_curve``: Almen intensity vs shot velocity, one curve per angle (paper §4, Fig. 17)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import ControlCurve

from ._common import SWEEP_COORDS, peening_task, var
from .outputs import Output, Outputs

_AV = ("angle_deg", "velocity_m_s")

OUTPUTS = Outputs(
    "control_curve",
    intensity_m=Output(_AV, "m", "Almen intensity"),
    intensity_std_m=Output(_AV, "m", "spread over sequences"),
    curve_intensity_m=Output(("angle_deg", "velocity_fine_m_s"), "m",
                             "interpolant of the control curve (attribute interpolation)"),
    monotone_increasing=Output(("angle_deg",), "1", "1 if intensity rises with velocity",
                               attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_increasing increasing"}),
    intensity_extrapolated=Output(_AV, "1", "1 if the saturation point lies outside the shot ladder",
                                  attrs={"flag_values": np.array([0, 1]),
                                         "flag_meanings": "within_ladder extrapolated"}),
    saturation_shots=Output(_AV, "1", "saturation point T, eq. (11)"),
    largest_shot_count=Output((), "1", "end of the saturation ladder (shots)"),
)


@peening_task(version="3")  # 3: intensities stored in m (was mm)
def control_curve(sat: xr.Dataset, *, interpolation: str) -> xr.Dataset:
    """``sat``: saturation results combined over (angle_deg, velocity_m_s).

    Returns the intensity table and, for plotting, each angle's interpolant
    (``interpolation``: "pchip" or "linear", the one ``target_velocity``
    inverts) sampled on a fine velocity grid.
    """
    table = sat.intensity_m.transpose(*_AV)
    v = sat.velocity_m_s.values.astype(float)
    fine = np.linspace(v.min(), v.max(), 61) if v.size > 1 else v.copy()
    curves = np.full((table.shape[0], fine.size), np.nan)
    increasing = np.zeros(table.shape[0], dtype=int)
    for i in range(table.shape[0]):
        ints = table.values[i]
        ok = np.isfinite(ints)
        if ok.sum() >= 2:
            curve = ControlCurve(float(table.angle_deg.values[i]), v[ok], ints[ok], interpolation)
            inside = (fine >= v[ok][0]) & (fine <= v[ok][-1])
            curves[i, inside] = curve.intensity(fine[inside])
            increasing[i] = int(curve.is_increasing)
    return OUTPUTS.dataset(
        {"intensity_m": table.values, "intensity_std_m": sat.intensity_std_m.transpose(*_AV).values,
         "curve_intensity_m": curves, "monotone_increasing": increasing,
         "intensity_extrapolated": sat.intensity_extrapolated.transpose(*_AV).values.astype(int),
         "saturation_shots": sat.saturation_shots.transpose(*_AV).values,
         "largest_shot_count": float(sat.shots.values.max())},
        coords={"angle_deg": var(table.angle_deg.values, ("angle_deg",), **SWEEP_COORDS["angle_deg"]),
                "velocity_m_s": var(v, ("velocity_m_s",), **SWEEP_COORDS["velocity_m_s"]),
                "velocity_fine_m_s": var(fine, ("velocity_fine_m_s",), "m s-1",
                                         "shot velocity (fine grid of the interpolant)")},
        attrs={"interpolation": interpolation},
    )
