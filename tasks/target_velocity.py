"""Stage ``target_velocity``: the shot velocity that gives the specified Almen intensity.

Paper §5: the velocity is read off the numerical control curve at the
target intensity -- at the computed angle nearest the part's impingement
angle (the paper uses its 67.5° curve for 65°), or interpolated linearly
between the two bracketing angles.  A study may instead give the velocity
directly (then there is no control curve upstream).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import ControlCurve, ControlCurveFamily

from ._common import MM, peening_task, var


class IntensityOutOfRange(ValueError):
    pass


@peening_task(version="1")
def target_velocity(control: xr.Dataset | None = None, *, intensity_mm: float | None,
                    angle_deg: float, rule: str = "nearest", velocity_m_s: float | None = None) -> xr.Dataset:
    if velocity_m_s is not None:
        return xr.Dataset({"velocity_m_s": var(velocity_m_s, (), "m/s", "given in the study")},
                          attrs={"method": "given"})
    curves = []
    for a in control.angle_deg.values:
        ints = control.intensity_mm.sel(angle_deg=a).values * MM
        v = control.velocity_m_s.values.astype(float)
        ok = np.isfinite(ints)
        if ok.sum() < 2:
            raise IntensityOutOfRange(f"control curve at {a} deg has fewer than 2 valid points")
        curves.append(ControlCurve(float(a), v[ok], ints[ok]))
    family = ControlCurveFamily(tuple(curves))
    curve = family.at_angle(angle_deg, "linear" if rule == "interpolate" else "nearest")
    lo, hi = curve.velocity_range
    i_lo, i_hi = sorted(float(x) for x in curve.intensity(np.array([lo, hi])))
    target = intensity_mm * MM
    if not i_lo <= target <= i_hi:
        raise IntensityOutOfRange(
            f"target intensity {intensity_mm:.4g} mm is outside the control curve at {angle_deg} deg, "
            f"which spans {i_lo / MM:.4g}-{i_hi / MM:.4g} mm over {lo:g}-{hi:g} m/s: add velocities to "
            "almen.velocities_m_s that bracket it"
        )
    v = float(curve.velocity(target))
    return xr.Dataset(
        {"velocity_m_s": var(v, (), "m/s", "velocity giving the target intensity on the control curve"),
         "intensity_mm": var(intensity_mm, (), "mm", "target Almen intensity")},
        attrs={"method": rule, "control_angles_deg": ", ".join(f"{a:g}" for a in family.angles)},
    )
