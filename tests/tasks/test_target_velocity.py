"""target_velocity: reading the velocity for an Almen intensity off the control curve."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from tasks.params import TargetParams
from tasks.target_velocity import ExtrapolatedIntensity, IntensityOutOfRange, target_velocity


def _read(control, intensity_mm, allow_extrapolated=False, interpolation="pchip"):
    """The stage at 90 deg, nearest curve, for ``intensity_mm``."""
    target = TargetParams(angle_deg=90.0, velocity_m_s=None, intensity_m=intensity_mm * 1e-3, rule="nearest",
                          interpolation=interpolation, allow_extrapolated=allow_extrapolated)
    return target_velocity.fn(control, target=target)


def _control(extrapolated, saturation_shots, largest=480.0):
    """A 90 deg control curve, intensity linear in velocity: 0.2/0.3/0.4 mm at 30/40/50 m/s."""
    v = np.array([30.0, 40.0, 50.0])
    dims = ("angle_deg", "velocity_m_s")
    return xr.Dataset(
        {"intensity_m": (dims, [[0.2e-3, 0.3e-3, 0.4e-3]]),
         "intensity_extrapolated": (dims, [extrapolated]),
         "saturation_shots": (dims, [saturation_shots]),
         "largest_shot_count": ((), largest)},
        coords={"angle_deg": [90.0], "velocity_m_s": v},
    )


def test_velocity_is_read_off_a_saturated_curve():
    # PCHIP through collinear points is the straight line: 0.25 mm -> 35 m/s exactly.
    ds = _read(_control([0, 0, 1], [100, 200, 900]), 0.25)
    assert float(ds.velocity_m_s) == pytest.approx(35.0, rel=1e-12)


def test_an_extrapolated_bracketing_point_stops_with_the_ladder_to_use():
    control = _control([0, 0, 1], [100, 200, 900])
    with pytest.raises(ExtrapolatedIntensity) as err:
        _read(control, 0.35)
    msg = str(err.value)
    assert "50 m/s at 90 deg: T = 900 shots" in msg and "largest shot count 480" in msg
    assert "2048" in msg  # next power of two above 2 T = 1800
    ds = _read(control, 0.35, allow_extrapolated=True)
    assert float(ds.velocity_m_s) == pytest.approx(45.0, rel=1e-12)


def test_an_intensity_outside_the_curve_names_the_range():
    with pytest.raises(IntensityOutOfRange, match="spans 0.2-0.4 mm over 30-50 m/s"):
        _read(_control([0, 0, 0], [100, 200, 300]), 0.45)


def test_outside_an_extrapolated_curve_the_ladder_is_what_is_reported():
    """The paper_al7075_standard case: every point extrapolated and 0.30 mm below
    them all -- the fix is a longer ladder, not more velocities."""
    control = _control([1, 1, 1], [2800, 1400, 900])
    with pytest.raises(ExtrapolatedIntensity, match="30 m/s at 90 deg: T = 2800 shots") as err:
        _read(control, 0.15)
    # ... and it says that the target is outside the curve as well (issue 12, 9b)
    assert str(err.value).startswith("target intensity 0.15 mm is outside the control curve at 90.0 deg, "
                                     "which spans 0.2-0.4 mm over 30-50 m/s; and the control curve is not saturated")
    assert "Extend almen.shot_counts" in str(err.value)
    with pytest.raises(IntensityOutOfRange):
        _read(control, 0.15, allow_extrapolated=True)


def test_linear_interpolation_is_what_the_velocity_is_read_from():
    """almen.interpolation = "linear" reaches the inverse (issue 9): on a curve
    with a kink the piecewise-linear inverse differs from PCHIP's."""
    v = np.array([30.0, 40.0, 50.0])
    dims = ("angle_deg", "velocity_m_s")
    control = xr.Dataset({"intensity_m": (dims, [[0.2e-3, 0.3e-3, 0.32e-3]]),
                          "intensity_extrapolated": (dims, [[0, 0, 0]]),
                          "saturation_shots": (dims, [[100, 200, 300]]), "largest_shot_count": ((), 480.0)},
                         coords={"angle_deg": [90.0], "velocity_m_s": v})
    linear = _read(control, 0.31, interpolation="linear")
    assert float(linear.velocity_m_s) == pytest.approx(45.0, rel=1e-12)  # halfway on the 40-50 m/s segment
    assert linear.attrs["interpolation"] == "linear"
    pchip = _read(control, 0.31)
    assert abs(float(pchip.velocity_m_s) - 45.0) > 0.5  # PCHIP bends with the kink: not the chord
