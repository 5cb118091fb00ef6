"""Saturation curves: arc height vs shot number, the 10 % rule and the Almen intensity.

Models (``N`` = number of shots, the paper's stand-in for exposure time):

* ``"eq10"`` -- the paper's eq. (10), ``Ah(N) = B/(N + d)^p - B/d^p``.
* ``"exp2"`` -- SAE J2597 two-parameter curve ``a (1 - exp(-b N))``.
* ``"exp3"`` -- SAE J2597 three-parameter curve ``a (1 - exp(-b N^c))``.

The saturation point solves eq. (11), ``Ah(2N) = 1.1 Ah(N)`` (the arc height
grows by 10 % when the exposure doubles); the intensity is ``Ah(N_sat)``.

Parametrisation of eq. (10). Fitting (B, d, p) directly is ill-posed: for an
increasing curve B and p must have opposite signs, B spans orders of magnitude
as d^p does, and p = 0 is a singular point. The identical family is written as

    Ah(N) = S * phi_p(N / d),   phi_p(x) = (1 - (1 + x)^(-p)) / p,   phi_0(x) = ln(1 + x),

with ``S = d * Ah'(0) > 0`` (initial slope times d) and ``B = -(S / p) d^p``.
It is continuous through p = 0, saturates to ``S/p`` for p > 0 and grows like a
power ``N^(-p)`` for p < 0. Because the model is linear in S, S is eliminated in
closed form (variable projection) and only (ln d, p) are searched: a coarse grid
gives a global starting point, then a bounded ``least_squares`` refines it.
The same scheme is used for the exponential models (a eliminated).

Least squares are on the arc height itself (unweighted), the measured quantity.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

import numpy as np
from scipy.optimize import brentq, least_squares

from ._arrays import read_only as _ro

#: the 10 % rule of eq. (11) and SAE J443/J2597
GROWTH_RATIO = 1.1

_P_BOUNDS = (-0.99, 50.0)  # eq. (10) exponent; p -> +inf approaches the exponential curve
_C_BOUNDS = (0.2, 5.0)  # exp3 exponent; 2^c must exceed 1.1 for eq. (11) to have a root


def _phi(x, p):
    """(1 - (1+x)^-p)/p, stable for small x and p (expm1/log1p)."""
    x = np.asarray(x, dtype=float)
    if abs(p) < 1e-10:
        return np.log1p(x)
    return -np.expm1(-p * np.log1p(x)) / p


def _basis(model: str, theta, n):
    if model == "eq10":
        lnd, p = theta
        return _phi(n / np.exp(lnd), p)
    if model == "exp2":
        (lnb,) = theta
        return -np.expm1(-np.exp(lnb) * n)
    if model == "exp3":
        lnb, c = theta
        return -np.expm1(-np.exp(lnb) * n**c)
    raise ValueError(f"unknown saturation model {model!r}; use 'eq10', 'exp2' or 'exp3'")


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class SaturationFit:
    """A fitted saturation curve and its saturation point.

    model : "eq10", "exp2" or "exp3".
    parameters : mapping of fitted parameters. eq10: S (m), d (shots), p (-),
        B (m·shots^p, the paper's B; NaN when p == 0); exp2: a (m), b (1/shot);
        exp3: a (m), b (1/shot^c), c (-).
    saturation_shots : N_sat solving eq. (11), shots (may be non-integer).
    intensity : Ah(N_sat), m (the Almen intensity when Ah is from an Almen strip).
    counts, arc_heights : (m,) the data fitted (shots, m).
    residuals : (m,) data minus model, m. residual_rms : m.
    extrapolated : N_sat lies outside [min(counts), max(counts)]; the intensity
        then rests on the model beyond the data (SAE J2597 asks for data on both sides).
    at_bound : a shape parameter ended on its search bound (fit less trustworthy).
    """

    model: str
    parameters: Mapping[str, float]
    saturation_shots: float
    intensity: float
    counts: np.ndarray = field(repr=False)
    arc_heights: np.ndarray = field(repr=False)
    residuals: np.ndarray = field(repr=False)
    residual_rms: float = 0.0
    extrapolated: bool = False
    at_bound: bool = False

    def arc_height(self, n) -> np.ndarray:
        """Model arc height (m) at shot numbers ``n`` (any shape)."""
        q = self.parameters
        n = np.asarray(n, dtype=float)
        if self.model == "eq10":
            return q["S"] * _phi(n / q["d"], q["p"])
        if self.model == "exp2":
            return q["a"] * -np.expm1(-q["b"] * n)
        return q["a"] * -np.expm1(-q["b"] * n ** q["c"])


def _validate(counts, arc_heights):
    n = np.asarray(counts, dtype=float)
    y = np.asarray(arc_heights, dtype=float)
    if n.ndim != 1 or y.shape != n.shape:
        raise ValueError(f"counts and arc_heights must be 1-D of equal length, got {n.shape} and {y.shape}")
    keep = np.isfinite(y)
    n, y = n[keep], y[keep]
    if not np.all(np.isfinite(n)) or np.any(n <= 0):
        raise ValueError("shot counts must be finite and positive")
    if np.unique(n).size < 3:
        raise ValueError(
            f"saturation needs arc heights at >= 3 distinct shot counts, got {np.unique(n).size}"
        )
    order = np.argsort(n, kind="stable")
    n, y = n[order], y[order]
    # Overall trend: least-squares slope of Ah against ln N. Every model here is
    # increasing through Ah(0) = 0, so it would still "fit" falling data with a
    # curve that saturates before the first point; refuse that explicitly.
    ln = np.log(n) - np.log(n).mean()
    if not float(ln @ (y - y.mean())) > 0 or not np.max(y) > 0:
        raise ValueError(
            "arc height does not increase with the number of shots (slope of Ah vs ln N <= 0): "
            "saturation is undefined; check the data order and the sign convention (Ah > 0)"
        )
    return n, y


def _project(model, theta, n, y):
    g = _basis(model, theta, n)
    gg = float(g @ g)
    amp = float(g @ y) / gg if gg > 0 else 0.0
    return amp, y - amp * g


def _fit_shape(model, n, y):
    """Grid search then bounded least squares over the non-linear parameters."""
    lo_n, hi_n = n.min(), n.max()
    if model == "eq10":
        grid = [np.linspace(np.log(lo_n) - 7, np.log(hi_n) + 7, 57),
                np.concatenate([np.linspace(-0.95, 3.0, 40), np.geomspace(3.5, 45.0, 12)])]
        bounds = ([np.log(lo_n) - 12, _P_BOUNDS[0]], [np.log(hi_n) + 12, _P_BOUNDS[1]])
    elif model == "exp2":
        grid = [np.linspace(-np.log(hi_n) - 5, -np.log(lo_n) + 5, 201)]
        bounds = ([-np.log(hi_n) - 12], [-np.log(lo_n) + 12])
    else:
        # b N^c ~ 1 near saturation, so ln b ~ -c ln N with c up to 5
        lnb_lo = -_C_BOUNDS[1] * np.log(hi_n)
        grid = [np.linspace(lnb_lo - 5, 8.0, 71), np.linspace(_C_BOUNDS[0], _C_BOUNDS[1], 49)]
        bounds = ([lnb_lo - 12, _C_BOUNDS[0]], [10.0, _C_BOUNDS[1]])
    best, best_cost = None, np.inf
    for theta in np.array(np.meshgrid(*grid, indexing="ij")).reshape(len(grid), -1).T:
        amp, r = _project(model, theta, n, y)
        cost = float(r @ r)
        if amp > 0 and cost < best_cost:
            best, best_cost = theta, cost
    if best is None:
        raise ValueError(
            "arc height does not increase with the number of shots: no saturation curve fits "
            "(check the data order and sign convention, Ah > 0 convex towards the peened side)"
        )
    scale = max(float(np.max(np.abs(y))), 1e-300)
    res = least_squares(
        lambda t: _project(model, t, n, y)[1] / scale,
        best,
        bounds=bounds,
        method="trf",
        x_scale=1.0,
        xtol=1e-12,
        ftol=1e-14,
        gtol=1e-14,
    )
    theta = res.x if 2 * res.cost * scale**2 <= best_cost * (1 + 1e-12) else best
    amp, r = _project(model, theta, n, y)
    if not amp > 0:
        raise ValueError("arc height does not increase with the number of shots: fitted amplitude <= 0")
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    width = hi - lo
    at_bound = bool(np.any(theta[1:] <= lo[1:] + 1e-6 * width[1:]) or np.any(theta[1:] >= hi[1:] - 1e-6 * width[1:])) if theta.size > 1 else False
    return theta, amp, r, at_bound


def _ratio_root(ratio, lo, hi, what):
    """Root of ratio(t) = 1.1 for t in [lo, hi] (t a log variable), ratio decreasing."""
    g_lo, g_hi = ratio(lo) - GROWTH_RATIO, ratio(hi) - GROWTH_RATIO
    if not g_lo > 0:
        raise ValueError(f"{what}: the curve already grows by less than 10 % per doubling at the start")
    if not g_hi < 0:
        raise ValueError(
            f"{what}: the fitted curve keeps growing by >= 10 % per doubling of N (limit ratio "
            f"{g_hi + GROWTH_RATIO:.4f}), so it cannot saturate; more shots are needed"
        )
    return brentq(lambda t: ratio(t) - GROWTH_RATIO, lo, hi, xtol=1e-14, rtol=1e-14, maxiter=500)


def eq10_saturation_x(p: float) -> float:
    """x* = N_sat / d solving eq. (11) for the eq. (10) family with exponent p."""
    def ratio(t):
        x = np.exp(t)
        return float(_phi(2 * x, p) / _phi(x, p))
    return float(np.exp(_ratio_root(ratio, -30.0, 300.0, f"eq. (10) with p = {p:.4g}")))


def _exp3_saturation_u(c: float) -> float:
    """u* = b N_sat^c solving (1 - e^(-2^c u)) / (1 - e^(-u)) = 1.1."""
    def ratio(t):
        u = np.exp(t)
        return float(np.expm1(-(2.0**c) * u) / np.expm1(-u))
    return float(np.exp(_ratio_root(ratio, -40.0, 6.0, f"exp3 with c = {c:.4g}")))


def fit_saturation(counts, arc_heights, model: str = "eq10") -> SaturationFit:
    """Fit a saturation curve to arc heights and solve eq. (11).

    Parameters
    ----------
    counts : (m,) shot numbers N > 0 (>= 3 distinct values).
    arc_heights : (m,) arc heights, m (NaN entries are dropped, e.g. failed runs).
    model : "eq10" (paper eq. 10), "exp2" or "exp3" (SAE J2597 style).

    Returns a SaturationFit. Raises ValueError, saying why, when the data cannot
    define saturation: fewer than 3 counts, arc height not increasing, or a
    fitted curve that never slows to 10 % growth per doubling.
    """
    n, y = _validate(counts, arc_heights)
    theta, amp, r, at_bound = _fit_shape(model, n, y)
    if model == "eq10":
        d, p = float(np.exp(theta[0])), float(theta[1])
        x = eq10_saturation_x(p)
        nsat = d * x
        B = -(amp / p) * d**p if abs(p) > 1e-10 else float("nan")
        params = {"S": amp, "d": d, "p": p, "B": B}
    elif model == "exp2":
        b = float(np.exp(theta[0]))
        nsat = np.log(10.0) / b  # 1 + exp(-b N) = 1.1 in closed form
        params = {"a": amp, "b": b}
    else:
        b, c = float(np.exp(theta[0])), float(theta[1])
        nsat = (_exp3_saturation_u(c) / b) ** (1.0 / c)
        params = {"a": amp, "b": b, "c": c}
    fit = SaturationFit(
        model=model,
        parameters=MappingProxyType(params),
        saturation_shots=float(nsat),
        intensity=0.0,
        counts=_ro(n),
        arc_heights=_ro(y),
        residuals=_ro(r),
        residual_rms=float(np.sqrt(np.mean(r**2))),
        extrapolated=bool(nsat < n.min() or nsat > n.max()),
        at_bound=at_bound,
    )
    object.__setattr__(fit, "intensity", float(fit.arc_height(nsat)))
    return fit



@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class SequenceSaturation:
    """Saturation fits of several random shot sequences.

    fits : per-sequence SaturationFit, or None where that sequence failed.
    errors : per-sequence error message, or None where it succeeded.
    mean_fit : fit of the sequence-mean arc-height curve, or of the pooled points
        where the sequences' ladders differ (see fit_sequences).
    intensity_mean, intensity_std (ddof=1; NaN if < 2 fits), intensity_min,
    intensity_max : statistics of the per-sequence intensities, m.
    """

    fits: tuple
    errors: tuple
    mean_fit: SaturationFit
    intensity_mean: float
    intensity_std: float
    intensity_min: float
    intensity_max: float


def fit_sequences(counts, arc_heights, model: str = "eq10") -> SequenceSaturation:
    """Fit each sequence and the mean curve.

    counts : (m,) shot numbers. arc_heights : (n_seq, m) arc heights, m; NaN marks
    a missing point.  ``mean_fit`` fits the sequence-mean curve where every
    sequence has data at the same counts, else (ladders of different lengths)
    the pooled points of all sequences. A sequence whose data cannot define saturation is recorded in
    ``errors``; the mean-curve fit must succeed or ValueError is raised.
    """
    y = np.atleast_2d(np.asarray(arc_heights, dtype=float))
    n = np.asarray(counts, dtype=float)
    if y.shape[1] != n.size:
        raise ValueError(f"arc_heights must have shape (n_seq, {n.size}), got {y.shape}")
    fits, errors = [], []
    for row in y:
        try:
            fits.append(fit_saturation(n, row, model))
            errors.append(None)
        except ValueError as exc:
            fits.append(None)
            errors.append(str(exc))
    finite = np.isfinite(y)
    rows = finite[finite.any(axis=1)]
    if rows.size and not np.all(rows == rows[0]):
        # Ladders of different lengths (almen.shot_counts = "auto" stops each
        # sequence at its own rung): a mean per N would, at the large N only the
        # long ladders reach, be the mean of those alone.  Least squares on the
        # pooled points weighs every measured point once; where every sequence
        # has the same counts it has the same minimiser as the mean-curve fit.
        mean_fit = fit_saturation(np.tile(n, y.shape[0]), y.ravel(), model)
    else:
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(finite, y, 0.0).sum(axis=0) / finite.sum(axis=0)
        mean_fit = fit_saturation(n, mean, model)
    vals = np.array([f.intensity for f in fits if f is not None])
    nan = float("nan")
    return SequenceSaturation(
        fits=tuple(fits),
        errors=tuple(errors),
        mean_fit=mean_fit,
        intensity_mean=float(vals.mean()) if vals.size else nan,
        intensity_std=float(vals.std(ddof=1)) if vals.size > 1 else nan,
        intensity_min=float(vals.min()) if vals.size else nan,
        intensity_max=float(vals.max()) if vals.size else nan,
    )
