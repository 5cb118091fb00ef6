"""A saturation ladder that extends itself (issue 10 §3): when to stop peening a strip.

A strip run with ``almen.shot_counts = "auto"`` peens a doubling ladder
N = first, 2 first, 4 first, ... (capped at ``max_shots``) and after each
relaxed rung fits the saturation curve to its own arc heights.  It stops as
soon as that fit's saturation point T (eq. 11) is *inside its own data* the
way SAE J2597 asks: a rung at N >= 2T (so Ah(2T) is measured, not
extrapolated) and T not below the first rung.  The user no longer guesses a
ladder; a run never goes on past the rung that settles eq. (11).

The decision is a pure function of the rungs' arc heights, so a resumed run
takes exactly the decisions the uninterrupted one took.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .saturation import fit_saturation


def doubling_ladder(first: int, cap: int) -> tuple[int, ...]:
    """``first, 2 first, 4 first, ...`` up to ``cap`` shots, ``cap`` itself the last rung.

    ``cap`` ends the ladder even where it is not a doubling (e.g. 10 ... 320,
    400 for cap 400), so the whole shot budget the user allowed is usable.
    Raises ValueError unless the ladder has the >= 3 rungs eq. (10) needs.
    """
    first, cap = int(first), int(cap)
    if first < 1 or cap < first:
        raise ValueError(f"a ladder needs 1 <= first ({first}) <= cap ({cap})")
    rungs = [first]
    while rungs[-1] * 2 <= cap:
        rungs.append(rungs[-1] * 2)
    if rungs[-1] != cap:
        rungs.append(cap)
    if len(rungs) < 3:
        raise ValueError(f"a ladder from {first} to {cap} shots has {len(rungs)} rungs; eq. (10) needs >= 3 "
                         f"(cap > 2 x first)")
    return tuple(rungs)


@dataclass(frozen=True)
class LadderVerdict:
    """Whether a ladder may stop after its last rung.

    stop : True when no further rung is needed (saturated, or more shots would
        not help because T lies below the first rung).
    saturated : eq. (11)'s point T has a rung at >= 2 T and T >= the first rung.
    saturation_shots : T of the fit to the rungs so far (NaN where no fit).
    reason : one sentence, for the result's record.
    """

    stop: bool
    saturated: bool
    saturation_shots: float
    reason: str


def ladder_verdict(counts, arc_heights_m, model: str = "eq10") -> LadderVerdict:
    """Decide from the rungs so far (shot counts, arc heights in m) whether to stop.

    ``model``: the saturation fit of the study (:func:`fit_saturation`'s names).
    Fewer than 3 rungs, or data that do not yet define saturation (arc height
    still growing >= 10 % per doubling), mean: go on.
    """
    n = np.asarray(counts, dtype=float)
    y = np.asarray(arc_heights_m, dtype=float)
    if np.isfinite(y).sum() < 3:
        return LadderVerdict(False, False, float("nan"), f"{np.isfinite(y).sum()} rung(s) so far: eq. (10) needs 3")
    try:
        fit = fit_saturation(n, y, model)
    except ValueError as exc:
        return LadderVerdict(False, False, float("nan"), f"no saturation yet: {exc}")
    t, lo, hi = fit.saturation_shots, float(n.min()), float(n.max())
    if t < lo:
        return LadderVerdict(True, False, t, f"T = {t:.4g} shots lies below the first rung ({lo:.0f}): "
                                             "more shots cannot bracket it; lower almen.first_shots")
    if 2.0 * t <= hi:
        return LadderVerdict(True, True, t, f"saturated: 2 T = {2 * t:.4g} <= {hi:.0f} shots (last rung)")
    return LadderVerdict(False, False, t, f"2 T = {2 * t:.4g} > {hi:.0f} shots (last rung): go on")
