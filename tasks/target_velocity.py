"""Stage ``target_velocity``: the shot velocity that gives the specified Almen intensity.

Paper §5: the velocity is read off the numerical control curve at the
target intensity -- at the computed angle nearest the part's impingement
angle (the paper uses its 67.5° curve for 65°), or interpolated linearly
between the two bracketing angles.  A study may instead give the velocity
directly (then there is no control curve upstream).

The two control-curve points that bracket the target must be saturated
within their shot ladder (eq. 11's T at most the largest N): an intensity
whose saturation point is extrapolated depends on the fit's tail, not on
data, so it stops the run with the ladder to use unless the study allows it.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import ControlCurve, ControlCurveFamily
from peenflow.methods.control_curve import AngleBlend

from ._common import MM, peening_task
from .outputs import Output, Outputs
from .params import TargetParams

OUTPUTS = Outputs(
    "target_velocity",
    velocity_m_s=Output((), "m s-1", "shot velocity of the target (attribute method: given, or how it was read "
                                     "off the control curve)"),
    intensity_m=Output((), "m", "target Almen intensity", optional=True),
)


class IntensityOutOfRange(ValueError):
    pass


class ExtrapolatedIntensity(ValueError):
    """A control-curve point the velocity would be read from is not saturated within its ladder."""


def _check_saturated(control: xr.Dataset, angles, velocities, context: str = "") -> None:
    """Refuse intensities whose eq. (11) saturation point lies beyond the ladder (module docstring);
    ``context`` opens the message (e.g. that the target is outside the curve as well)."""
    if "intensity_extrapolated" not in control:
        return
    bad = []
    for a in angles:
        for v in velocities:
            point = control.sel(angle_deg=a, velocity_m_s=v)
            if int(point.intensity_extrapolated):
                bad.append(f"{v:g} m/s at {a:g} deg: T = {float(point.saturation_shots):.0f} shots")
    if bad:
        n_max = float(control.largest_shot_count)
        t_max = max(float(control.saturation_shots.sel(angle_deg=a, velocity_m_s=v))
                    for a in angles for v in velocities)
        suggest = int(2 ** np.ceil(np.log2(max(2 * t_max, 2 * n_max))))
        raise ExtrapolatedIntensity(
            f"{context}the control curve is not saturated where the target intensity is read: {'; '.join(bad)} "
            f"(largest shot count {n_max:.0f}). An intensity extrapolated beyond the ladder is not an Almen "
            f"intensity (SAE J2597 needs a point at 2 T). Extend almen.shot_counts to about {suggest} shots "
            "(the strip runs then restart from scratch for the new ladder; with shot_counts = \"auto\" raise "
            "almen.max_shots), or set "
            "almen.allow_extrapolated_intensity = true to accept it."
        )


@peening_task(version="3")  # 3: intensities stored in m (was mm)
def target_velocity(control: xr.Dataset | None = None, *, target: TargetParams) -> xr.Dataset:
    """The velocity on the control curve (``target.interpolation``: "pchip" or
    "linear" in velocity, as ``almen.interpolation``) at the target intensity."""
    angle_deg, rule, velocity_m_s = target.angle_deg, target.rule, target.velocity_m_s
    allow_extrapolated, interpolation = target.allow_extrapolated, target.interpolation
    wanted = target.intensity_m
    if velocity_m_s is not None:
        return OUTPUTS.dataset({"velocity_m_s": velocity_m_s}, attrs={"method": "given"})
    curves = []
    for a in control.angle_deg.values:
        ints = control.intensity_m.sel(angle_deg=a).values
        v = control.velocity_m_s.values.astype(float)
        ok = np.isfinite(ints)
        if ok.sum() < 2:
            raise IntensityOutOfRange(f"control curve at {a} deg has fewer than 2 valid points")
        curves.append(ControlCurve(float(a), v[ok], ints[ok], interpolation))
    family = ControlCurveFamily(tuple(curves))
    curve = family.at_angle(angle_deg, "linear" if rule == "interpolate" else "nearest")
    lo, hi = curve.velocity_range
    i_lo, i_hi = sorted(float(x) for x in curve.intensity(np.array([lo, hi])))
    blended = isinstance(curve, AngleBlend)
    used = (curve.lower.angle_deg, curve.upper.angle_deg) if blended else (curve.angle_deg,)
    grid = control.velocity_m_s.values.astype(float)
    if not i_lo <= wanted <= i_hi:
        outside = (f"target intensity {wanted / MM:.4g} mm is outside the control curve at {angle_deg} deg, "
                   f"which spans {i_lo / MM:.4g}-{i_hi / MM:.4g} mm over {lo:g}-{hi:g} m/s")
        if not allow_extrapolated:
            # An extrapolated curve's range says little about the velocities
            # needed: the ladder is the first problem to fix, but say both.
            _check_saturated(control, used, grid, context=f"{outside}; and ")
        raise IntensityOutOfRange(f"{outside}: add velocities to almen.velocities_m_s that bracket it")
    v = float(curve.velocity(wanted))
    if not allow_extrapolated:
        bracket = sorted({float(grid[grid <= v].max()), float(grid[grid >= v].min())})
        _check_saturated(control, used, bracket)
    return OUTPUTS.dataset(
        {"velocity_m_s": v, "intensity_m": wanted},
        attrs={"method": rule, "interpolation": interpolation,
               "control_angles_deg": ", ".join(f"{a:g}" for a in family.angles)},
    )
