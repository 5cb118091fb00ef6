"""Control curves: PCHIP interpolation, inverse, range errors, angle interpolation."""

import numpy as np
import pytest

from peenflow.methods.control_curve import AngleBlend, ControlCurve, ControlCurveFamily, control_angles

V = np.array([25.0, 35.0, 45.0, 55.0])  # the paper's velocities (§4)


def test_linear_data_reproduced_exactly_and_inverted():
    c = ControlCurve(90.0, V, 6e-6 * V)  # PCHIP reproduces linear functions
    v = np.linspace(25, 55, 31)
    np.testing.assert_allclose(c.intensity(v), 6e-6 * v, rtol=1e-13)
    np.testing.assert_allclose(c.velocity(6e-6 * v), v, rtol=1e-10)


def test_monotone_without_overshoot_and_round_trip():
    # concave, steeply varying data where a cubic spline would overshoot
    c = ControlCurve(67.5, V, [0.10e-3, 0.25e-3, 0.29e-3, 0.30e-3])
    v = np.linspace(25, 55, 601)
    i = c.intensity(v)
    assert np.all(np.diff(i) >= 0)
    assert i.max() <= 0.30e-3 * (1 + 1e-14)
    np.testing.assert_allclose(c.intensity(V), c.intensities, rtol=1e-14)
    targets = np.array([0.12e-3, 0.2e-3, 0.295e-3])
    np.testing.assert_allclose(c.intensity(c.velocity(targets)), targets, rtol=1e-10)


def test_out_of_range_raises_and_extrapolation_is_linear_with_end_slope():
    c = ControlCurve(45.0, V, [0.1e-3, 0.16e-3, 0.21e-3, 0.25e-3])
    with pytest.raises(ValueError, match="outside"):
        c.intensity(60.0)
    with pytest.raises(ValueError, match="outside"):
        c.velocity(0.3e-3)
    eps = 1e-6
    slope = (c.intensity(55.0) - c.intensity(55.0 - eps)) / eps
    assert c.intensity(60.0, extrapolate=True) == pytest.approx(0.25e-3 + 5 * slope, rel=1e-5)
    v = c.velocity(0.26e-3, extrapolate=True)
    assert v > 55 and c.intensity(v, extrapolate=True) == pytest.approx(0.26e-3, rel=1e-10)


def test_non_monotone_curve_cannot_be_inverted():
    c = ControlCurve(90.0, V, [0.1e-3, 0.2e-3, 0.19e-3, 0.3e-3])
    c.intensity(40.0)  # evaluation is fine
    with pytest.raises(ValueError, match="not strictly increasing"):
        c.velocity(0.15e-3)


def test_family_nearest_and_linear_in_angle():
    c45 = ControlCurve(45.0, V, 4e-6 * V)
    c675 = ControlCurve(67.5, V, 5e-6 * V)
    c90 = ControlCurve(90.0, V, 6e-6 * V)
    fam = ControlCurveFamily((c90, c45, c675))
    assert fam.angles == (45.0, 67.5, 90.0)
    assert fam.at_angle(65.0, "nearest") is c675  # the paper's choice for 65° (§5)
    assert fam.at_angle(90.0, "linear") is c90
    blend = fam.at_angle(56.25, "linear")
    assert isinstance(blend, AngleBlend) and blend.weight == pytest.approx(0.5)
    assert blend.intensity(40.0) == pytest.approx(4.5e-6 * 40.0, rel=1e-13)
    assert blend.velocity(4.5e-6 * 47.0) == pytest.approx(47.0, rel=1e-10)
    with pytest.raises(ValueError, match="no extrapolation"):
        fam.at_angle(30.0, "linear")
    # a tie goes to the larger, more normal angle
    assert ControlCurveFamily((c45, c90)).at_angle(67.5, "nearest") is c90


def test_bad_data_rejected():
    with pytest.raises(ValueError, match="strictly increasing"):
        ControlCurve(90.0, [25, 25, 35], [1, 2, 3])
    with pytest.raises(ValueError):
        ControlCurve(90.0, [25], [1e-4])


def test_control_angles_nearest_and_linear():
    angles = (45.0, 67.5, 90.0)
    assert control_angles(angles, 60.0) == ((67.5, 1.0),)
    assert control_angles(angles, 56.25) == ((67.5, 1.0),)  # tie -> larger angle
    (a0, w0), (a1, w1) = control_angles(angles, 50.625, "linear")
    assert (a0, a1) == (45.0, 67.5) and w0 == pytest.approx(0.75) and w1 == pytest.approx(0.25)
    assert control_angles(angles, 90.0, "linear") == ((90.0, 1.0),)
    with pytest.raises(ValueError, match="outside the computed angles"):
        control_angles(angles, 30.0, "linear")
