"""Control curves: Almen intensity vs shot velocity, per impingement angle (paper §3.2.1, §4, Fig. 17).

A control curve is known at a few velocities (the paper: 25, 35, 45, 55 m/s).
It is interpolated with PCHIP (piecewise cubic Hermite, Fritsch-Carlson
slopes; ``interpolation="pchip"``, the default) or piecewise linearly
(``"linear"``); both preserve monotonicity. PCHIP: an increasing data set gives an
increasing curve with no overshoot, so the inverse (the velocity that gives a
target intensity, §5: 12A = 0.3 mm -> 47 m/s at 67.5°) is unique. PCHIP also
reproduces linear data exactly.

Outside the data range, evaluation raises ValueError unless
``extrapolate=True``, which continues the curve *linearly* with its end slope
(monotone, unlike the end cubic); the caller who asks for it knows the value
is outside the computed range.

Intermediate angles (§5 uses the 67.5° curve for a 65° process): ``"nearest"``
returns the curve of the nearest computed angle; ``"linear"`` blends the two
neighbouring curves linearly in angle at equal velocity,
``I(v, θ) = (1 - w) I_lo(v) + w I_hi(v)``, ``w = (θ - θ_lo)/(θ_hi - θ_lo)``,
on the velocity range common to both; a convex combination of increasing
curves is increasing, so it is invertible too.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator, make_interp_spline
from scipy.optimize import brentq

from ._arrays import read_only as _ro



@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class ControlCurve:
    """Intensity vs velocity at one impingement angle.

    angle_deg : deg. velocities : (k,) m/s, strictly increasing, k >= 2.
    intensities : (k,) m, Almen intensity (saturation arc height) at each velocity.
    interpolation : "pchip" (monotone cubic) or "linear" (piecewise linear).
    """

    angle_deg: float
    velocities: np.ndarray
    intensities: np.ndarray
    interpolation: str = "pchip"
    _pchip: PchipInterpolator = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        v = _ro(self.velocities)
        i = _ro(self.intensities)
        if v.ndim != 1 or v.shape != i.shape or v.size < 2:
            raise ValueError("velocities and intensities must be 1-D of equal length >= 2")
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(i))):
            raise ValueError("control-curve data must be finite")
        if np.any(np.diff(v) <= 0):
            raise ValueError("velocities must be strictly increasing")
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "intensities", i)
        if self.interpolation == "pchip":
            interpolant = PchipInterpolator(v, i, extrapolate=False)
        elif self.interpolation == "linear":
            interpolant = make_interp_spline(v, i, k=1)
        else:
            raise ValueError(f"interpolation = {self.interpolation!r}: expected 'pchip' or 'linear'")
        object.__setattr__(self, "_pchip", interpolant)

    @property
    def velocity_range(self) -> tuple[float, float]:
        return float(self.velocities[0]), float(self.velocities[-1])

    @property
    def is_increasing(self) -> bool:
        return bool(np.all(np.diff(self.intensities) > 0))

    def intensity(self, velocity, extrapolate: bool = False) -> np.ndarray:
        """Intensity (m) at velocities (m/s, any shape); see module docstring for extrapolation."""
        v = np.asarray(velocity, dtype=float)
        lo, hi = self.velocity_range
        out = self._pchip(np.clip(v, lo, hi))
        below, above = v < lo, v > hi
        if np.any(below | above):
            if not extrapolate:
                raise ValueError(
                    f"velocity outside the control curve's range [{lo}, {hi}] m/s at {self.angle_deg}°; "
                    "pass extrapolate=True to extend it linearly"
                )
            d = self._pchip.derivative()
            out = np.where(below, self.intensities[0] + d(lo) * (v - lo), out)
            out = np.where(above, self.intensities[-1] + d(hi) * (v - hi), out)
        return out

    def velocity(self, intensity, extrapolate: bool = False) -> np.ndarray:
        """Velocity (m/s) giving the target intensity (m); inverse of :meth:`intensity`."""
        return _invert(self, intensity, extrapolate)


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class AngleBlend:
    """Linear-in-angle blend of two control curves (same interface as ControlCurve).

    angle_deg : the requested angle. lower, upper : the neighbouring curves.
    weight : w in ``(1 - w) I_lower + w I_upper``.
    """

    angle_deg: float
    lower: ControlCurve
    upper: ControlCurve
    weight: float

    @property
    def velocity_range(self) -> tuple[float, float]:
        a, b = self.lower.velocity_range, self.upper.velocity_range
        lo, hi = max(a[0], b[0]), min(a[1], b[1])
        if not lo < hi:
            raise ValueError("the two control curves share no velocity range")
        return lo, hi

    @property
    def is_increasing(self) -> bool:
        return self.lower.is_increasing and self.upper.is_increasing

    def intensity(self, velocity, extrapolate: bool = False) -> np.ndarray:
        v = np.asarray(velocity, dtype=float)
        lo, hi = self.velocity_range
        if not extrapolate and np.any((v < lo) | (v > hi)):
            raise ValueError(f"velocity outside the blended curves' common range [{lo}, {hi}] m/s")
        w = self.weight
        return (1 - w) * self.lower.intensity(v, extrapolate) + w * self.upper.intensity(v, extrapolate)

    def velocity(self, intensity, extrapolate: bool = False) -> np.ndarray:
        return _invert(self, intensity, extrapolate)


def _invert(curve, intensity, extrapolate):
    if not curve.is_increasing:
        raise ValueError(
            f"control curve at {curve.angle_deg}° is not strictly increasing in velocity; "
            "its inverse (velocity for a target intensity) is not unique"
        )
    target = np.asarray(intensity, dtype=float)
    lo, hi = curve.velocity_range
    i_lo, i_hi = (float(x) for x in curve.intensity(np.array([lo, hi])))
    out = np.empty(target.shape)
    flat = out.reshape(-1)
    for k, t in enumerate(target.reshape(-1)):
        if i_lo <= t <= i_hi:
            flat[k] = lo if t == i_lo else hi if t == i_hi else brentq(
                lambda v: float(curve.intensity(v)) - t, lo, hi, xtol=1e-12, rtol=1e-14
            )
        elif not extrapolate:
            raise ValueError(
                f"target intensity {t} m outside the control curve's range [{i_lo}, {i_hi}] m "
                f"at {curve.angle_deg}°; pass extrapolate=True to extend it linearly"
            )
        else:
            # the linear extension is invertible in closed form: bracket generously and solve
            span = hi - lo
            a, b = (lo - span, lo) if t < i_lo else (hi, hi + span)
            while (float(curve.intensity(a, True)) - t) * (float(curve.intensity(b, True)) - t) > 0:
                a, b = (a - 2 * span, b) if t < i_lo else (a, b + 2 * span)
                span *= 2
            flat[k] = brentq(lambda v: float(curve.intensity(v, True)) - t, a, b, xtol=1e-12, rtol=1e-14)
    return out


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class ControlCurveFamily:
    """Control curves at several angles; ``curves`` sorted by angle on construction."""

    curves: tuple

    def __post_init__(self):
        cs = tuple(sorted(self.curves, key=lambda c: c.angle_deg))
        if not cs:
            raise ValueError("need at least one control curve")
        angles = [c.angle_deg for c in cs]
        if len(set(angles)) != len(angles):
            raise ValueError(f"duplicate angles in control-curve family: {angles}")
        object.__setattr__(self, "curves", cs)

    @property
    def angles(self) -> tuple[float, ...]:
        return tuple(c.angle_deg for c in self.curves)

    def at_angle(self, angle_deg: float, method: str = "nearest"):
        """The curve to use at ``angle_deg`` (:func:`control_angles`): the nearest
        computed angle's curve, or the "linear" blend of the two around it."""
        chosen = control_angles(self.angles, angle_deg, method)
        by_angle = dict(zip(self.angles, self.curves))
        if len(chosen) == 1:
            return by_angle[chosen[0][0]]
        (lo, _), (hi, w) = chosen
        return AngleBlend(float(angle_deg), by_angle[lo], by_angle[hi], float(w))


def control_angles(angles, angle_deg: float, method: str = "nearest") -> tuple[tuple[float, float], ...]:
    """(computed angle in deg, weight) pairs that make the control curve at ``angle_deg``.

    angles : the computed angles, increasing. "nearest": the closest one,
    weight 1; a tie goes to the larger, more normal angle (the harder-hitting
    curve, so the velocity read off it is the lower, conservative one).
    "linear": the two bracketing angles with linear weights, ``(lo, 1 - w),
    (hi, w)``, ``w = (θ - θ_lo) / (θ_hi - θ_lo)``; an exact hit is one angle,
    weight 1. ValueError outside the computed range for "linear".
    """
    angles = [float(a) for a in angles]
    if angle_deg in angles:
        return ((float(angle_deg), 1.0),)
    if method == "nearest":
        return ((min(angles, key=lambda a: (abs(a - angle_deg), -a)), 1.0),)
    if method == "linear":
        if not angles[0] < angle_deg < angles[-1]:
            raise ValueError(
                f"{angle_deg}° outside the computed angles [{angles[0]}, {angles[-1]}]°: no extrapolation in angle"
            )
        k = bisect.bisect_left(angles, angle_deg)
        lo, hi = angles[k - 1], angles[k]
        w = (angle_deg - lo) / (hi - lo)
        return ((lo, 1.0 - w), (hi, w))
    raise ValueError("method must be 'nearest' or 'linear'")
