"""Almen intensity of measured strips: three saturation fits, a verdict on each, one reported.

A shop peens Almen strips for several exposures (time, passes, shots or
coverage: any positive measure of exposure, in any unit) and measures their
arc heights. The intensity is the arc height at the saturation point T, where
doubling the exposure raises the arc height by 10 % (eq. (11), SAE J443); T is
found on a curve fitted to the strips, never read off a single strip.

Each of the three curves of :mod:`.saturation` is fitted -- the paper's eq.
(10) and SAE J2597's two- and three-parameter exponentials -- and judged:

* residual: the RMS misfit and the residual standard error
  ``s = sqrt(SSR / (n - k))`` (n strips, k parameters), which charges a fit
  for each parameter it spends;
* at bound: a shape parameter (exp3's ``c``, eq. (10)'s ``p``) ended on its
  search bound, so the optimum lies outside the family searched;
* bracketing, as SAE J2597 asks of a saturation curve: a strip at or below T
  (else T is extrapolated below the data) and a strip at or beyond 2 T (else
  the 10 % rise that defines T is extrapolated above it).

The reported fit is, among those that pass all three checks, the one with the
smallest ``s``; equal ``s`` (within round-off) goes to the fit with fewer
parameters. SAE J2597 accepts any algorithm that reproduces its validation data
sets within 0.001 in; this rule is peenflow's own. Where no fit passes, the
best of the rest is reported with ``qualified`` False -- unless its T lies
beyond the longest exposure (no strip reached saturation): that is refused.

Data checks come first (:class:`StripDataError`, naming the points): at least
4 distinct exposures, and an arc height that rises with exposure and never
falls below that of a shorter exposure by more than 0.001 in (SAE J2597's
tolerance on an intensity; smaller dips are gauge and strip scatter).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .saturation import GROWTH_RATIO, SaturationFit, fit_saturation

__all__ = ["MIN_EXPOSURES", "DROP_TOLERANCE_M", "MODELS", "FitVerdict", "StripIntensity", "StripDataError",
           "check_strips", "strip_intensity"]

#: distinct exposures a saturation curve needs (SAE J443 / J2597 practice: 4 strips at least)
MIN_EXPOSURES = 4
#: a fall in mean arc height larger than this is bad data, not scatter: SAE J2597's
#: acceptance tolerance on an intensity, 0.001 in
DROP_TOLERANCE_M = 0.001 * 0.0254
#: the fits tried, simplest first (the order breaks ties in s): name -> (parameters, formula)
MODELS = {
    "exp2": (2, "a (1 - exp(-b t))"),
    "exp3": (3, "a (1 - exp(-b t^c))"),
    "eq10": (3, "B/(t + d)^p - B/d^p"),
}
_SHAPE = {"exp3": "c", "eq10": "p"}  # the parameter whose bound at_bound reports
_TIE = 1e-9  # relative to the largest arc height: s values closer than this are equal (round-off)


class StripDataError(ValueError):
    """The strips cannot define an intensity; the message names the points and what is expected."""


@dataclass(frozen=True)
class FitVerdict:
    """One saturation fit to the strips, and what it is worth.

    model : "exp2", "exp3" or "eq10" (see MODELS). fit : the SaturationFit, None where
    it failed (``error`` says why). n_parameters : k. residual_rms_m, residual_se_m :
    RMS misfit and ``sqrt(SSR / (n - k))``, m (NaN where failed). at_bound : names of
    shape parameters on their search bound. below_first : T < the shortest exposure.
    short_of_2t : 2 T > the longest exposure (no strip at or beyond 2 T).
    """

    model: str
    fit: SaturationFit | None
    error: str | None
    n_parameters: int
    residual_rms_m: float
    residual_se_m: float
    at_bound: tuple[str, ...]
    below_first: bool
    short_of_2t: bool

    @property
    def ok(self) -> bool:
        return self.fit is not None

    @property
    def extrapolated(self) -> bool:
        """T or 2 T lies outside the strips' exposures."""
        return self.below_first or self.short_of_2t

    @property
    def qualified(self) -> bool:
        """Fitted, no parameter on a bound, T bracketed by strips as SAE J2597 asks."""
        return self.ok and not self.at_bound and not self.extrapolated

    def problems(self, shown_as: tuple[str, float] = ("", 1.0)) -> list[str]:
        """Why the fit is not qualified (empty when it is); exposures shown as ``shown_as``
        (unit, factor from the exposures given), as in :func:`strip_intensity`."""
        if not self.ok:
            return [f"no fit: {self.error}"]
        out = [f"{name} = {self.fit.parameters[name]:.4g} on its search bound" for name in self.at_bound]
        t = self.fit.saturation_shots
        if self.below_first:
            out.append(f"T = {_show(t, shown_as)} below the shortest exposure {_show(self.fit.counts.min(), shown_as)}")
        if self.short_of_2t:
            out.append(f"2T = {_show(2 * t, shown_as)} beyond the longest exposure "
                       f"{_show(self.fit.counts.max(), shown_as)}")
        return out


@dataclass(frozen=True)
class StripIntensity:
    """The Almen intensity of a set of strips.

    intensity_m : arc height at T on the reported fit, m. saturation_exposure : T, in
    the unit of the exposures given. model : the reported fit (a key of MODELS).
    qualified : that fit passed every check (see FitVerdict.qualified); False means
    the intensity is extrapolated or rests on a fit at a bound. reason : one sentence
    on why this fit is reported. verdicts : one FitVerdict per model, MODELS order.
    n_strips, n_exposures : points and distinct exposures fitted. shown_as : (unit,
    factor) the messages show exposures in (see strip_intensity).
    """

    intensity_m: float
    saturation_exposure: float
    model: str
    qualified: bool
    reason: str
    verdicts: tuple[FitVerdict, ...]
    n_strips: int
    n_exposures: int
    shown_as: tuple[str, float] = ("", 1.0)

    @property
    def chosen(self) -> FitVerdict:
        return next(v for v in self.verdicts if v.model == self.model)

    def record(self) -> dict:
        """Plain values for a result's attributes: the reported fit and each fit's verdict."""
        out = {"intensity_m": self.intensity_m, "saturation_exposure": self.saturation_exposure,
               "fit": self.model, "qualified": int(self.qualified), "fit_reason": self.reason}
        for v in self.verdicts:
            out[f"{v.model}_intensity_m"] = v.fit.intensity if v.ok else float("nan")
            out[f"{v.model}_residual_se_m"] = v.residual_se_m
            out[f"{v.model}_verdict"] = "qualified" if v.qualified else "; ".join(v.problems(self.shown_as))
        return out


def _labels(labels, n) -> list[str]:
    if labels is None:
        return [f"point {i + 1}" for i in range(n)]
    labels = [str(s) for s in labels]
    if len(labels) != n:
        raise ValueError(f"labels: {len(labels)} given for {n} points")
    return labels


def _join(names) -> str:
    return ", ".join(names)


def _show(x: float, shown_as: tuple[str, float]) -> str:
    unit, factor = shown_as
    return f"{x * factor:.4g}" + (f" {unit}" if unit else "")


def check_strips(exposure, arc_height_m, labels: Sequence[str] | None = None,
                 shown_as: tuple[str, float] = ("", 1.0)) -> None:
    """Refuse strips that cannot define a saturation curve; StripDataError names the points.

    exposure : (n,) exposures > 0 (any unit). arc_height_m : (n,) arc heights >= 0, m.
    labels : (n,) how to name each point in a message (e.g. "line 7"); default "point i".
    shown_as : (unit, factor) to show exposures in messages, e.g. ("min", 1/60) for s.
    """
    t = np.asarray(exposure, dtype=float)
    y = np.asarray(arc_height_m, dtype=float)
    if t.ndim != 1 or y.shape != t.shape:
        raise ValueError(f"exposure and arc_height_m must be 1-D of equal length, got {t.shape} and {y.shape}")
    names = _labels(labels, t.size)
    bad = [names[i] for i in range(t.size) if not (np.isfinite(t[i]) and t[i] > 0)]
    if bad:
        raise StripDataError(f"exposure must be a finite number > 0 at {_join(bad)}")
    bad = [names[i] for i in range(t.size) if not (np.isfinite(y[i]) and y[i] >= 0)]
    if bad:
        raise StripDataError(f"arc height must be a finite number >= 0 at {_join(bad)}")
    levels = np.unique(t)
    groups = [np.flatnonzero(t == v) for v in levels]

    def at(j: int) -> str:  # "8 min (line 9, line 10)"
        return f"{_show(levels[j], shown_as)} ({_join(names[i] for i in groups[j])})"

    if levels.size < MIN_EXPOSURES:
        raise StripDataError(
            f"strips at {levels.size} distinct exposure(s): {'; '.join(at(j) for j in range(levels.size))}; a "
            f"saturation curve needs strips at >= {MIN_EXPOSURES} distinct exposures, bracketing the saturation "
            "point T (one at or below T, one at or beyond 2T)")
    means = np.array([y[g].mean() for g in groups])
    # Past saturation the arc height is flat within scatter; a fall larger than SAE J2597's
    # own tolerance means something changed during the test (air pressure, shot flow, strips).
    top = 0
    for j in range(1, levels.size):
        if means[j] < means[top] - DROP_TOLERANCE_M:
            raise StripDataError(
                f"arc height falls with exposure: {1e3 * means[j]:.4g} mm at {at(j)} against "
                f"{1e3 * means[top]:.4g} mm at the shorter {at(top)}; expected an arc height that rises with "
                "exposure (falls up to 0.001 in are taken as scatter)")
        if means[j] > means[top]:
            top = j
    if not means[-1] > means[0]:
        raise StripDataError(
            f"arc height does not increase: {1e3 * means[-1]:.4g} mm at the longest exposure {at(-1)} against "
            f"{1e3 * means[0]:.4g} mm at the shortest {at(0)}; expected strips from below saturation to beyond it")


def _verdict(model: str, t, y) -> FitVerdict:
    k = MODELS[model][0]
    nan = float("nan")
    try:
        fit = fit_saturation(t, y, model)
    except ValueError as exc:
        return FitVerdict(model, None, str(exc), k, nan, nan, (), False, False)
    ssr = float(fit.residuals @ fit.residuals)
    ts = fit.saturation_shots
    return FitVerdict(
        model=model,
        fit=fit,
        error=None,
        n_parameters=k,
        residual_rms_m=fit.residual_rms,
        residual_se_m=float(np.sqrt(ssr / (t.size - k))),
        at_bound=(_SHAPE[model],) if fit.at_bound else (),
        below_first=bool(ts < t.min()),
        short_of_2t=bool(2.0 * ts > t.max()),
    )


def _smallest_se(pool: list[FitVerdict], scale: float) -> FitVerdict:
    best = min(v.residual_se_m for v in pool)
    return next(v for v in pool if v.residual_se_m <= best + _TIE * scale)  # pool is simplest first


def strip_intensity(exposure, arc_height_m, labels: Sequence[str] | None = None,
                    shown_as: tuple[str, float] = ("", 1.0)) -> StripIntensity:
    """Fit the three saturation curves to measured strips and report the intensity.

    exposure : (n,) exposure of each strip, > 0, any unit (the saturation exposure
        comes back in it); several strips may share an exposure.
    arc_height_m : (n,) arc heights, m.
    labels : (n,) names of the points for messages (e.g. "line 7").
    shown_as : (unit, factor) to show exposures in messages: the exposure given times
        factor, in unit (e.g. ("min", 1/60) for exposures given in s).

    Returns a StripIntensity. Raises StripDataError (check_strips' checks; no
    curve defines T; or no strip reached T: the arc height still rises >= 10 % per
    doubling at the longest exposure).
    """
    check_strips(exposure, arc_height_m, labels, shown_as)
    t = np.asarray(exposure, dtype=float)
    y = np.asarray(arc_height_m, dtype=float)
    verdicts = tuple(_verdict(m, t, y) for m in MODELS)
    fitted = [v for v in verdicts if v.ok]
    if not fitted:
        why = "; ".join(f"{v.model}: {v.error}" for v in verdicts)
        raise StripDataError(
            f"no saturation curve defines T for these strips ({why}); if the arc height still rises "
            f"{100 * (GROWTH_RATIO - 1):.0f} % or more when the exposure doubles, add strips at longer exposures")
    scale = float(np.max(y))
    qualified = [v for v in verdicts if v.qualified]
    if qualified:
        pick = _smallest_se(qualified, scale)
        others = "" if len(qualified) == 1 else f" of the {len(qualified)} that pass"
        reason = (f"{pick.model} passes every check (T bracketed by strips, one at or beyond 2T, no parameter on "
                  f"a bound) and has the smallest residual standard error{others}")
    else:
        free = [v for v in fitted if not v.at_bound]
        pick = _smallest_se(free or fitted, scale)
        t_sat = pick.fit.saturation_shots
        if t_sat > t.max():
            # Not one strip reached T: the "intensity" would be the curve's guess far beyond
            # the data (for a straight line, at T ~ 1e10), not a measurement.
            raise StripDataError(
                f"the strips have not reached saturation: the best fit ({pick.model}) puts T at "
                f"{_show(t_sat, shown_as)}, beyond the longest exposure {_show(t.max(), shown_as)}; add strips at "
                f"longer exposures, up to at least 2T")
        reason = (f"no fit passes every check, so the intensity is not qualified (SAE J2597 wants T bracketed: a "
                  f"strip at or below T and one at or beyond 2T); {pick.model} has the smallest residual standard "
                  f"error of the fits{' with no parameter on a bound' if free else ''}: "
                  + "; ".join(pick.problems(shown_as)))
    return StripIntensity(
        intensity_m=pick.fit.intensity,
        saturation_exposure=pick.fit.saturation_shots,
        model=pick.model,
        qualified=pick.qualified,
        reason=reason,
        verdicts=verdicts,
        n_strips=int(t.size),
        n_exposures=int(np.unique(t).size),
        shown_as=shown_as,
    )
