"""The self-extending saturation ladder (issue 10 §3): the doubling ladder and its stop rule.

"Stops when it should and not before": on a known eq. (10) curve, walking the
doubling ladder rung by rung, the first rung at which the rule says stop is
the first rung at >= 2T of the exact curve, and the intensity there is the
exact one."""

import numpy as np
import pytest

from peenflow.methods import doubling_ladder, ladder_verdict
from peenflow.methods.saturation import eq10_saturation_x, fit_saturation


def eq10_paper(n, B, d, p):
    """Eq. (10) exactly as printed in the paper."""
    return B / (n + d) ** p - B / d**p


def test_doubling_ladder_doubles_and_ends_at_the_cap():
    assert doubling_ladder(10, 320) == (10, 20, 40, 80, 160, 320)
    assert doubling_ladder(10, 400) == (10, 20, 40, 80, 160, 320, 400)  # the whole budget is usable
    assert doubling_ladder(3, 12) == (3, 6, 12)
    assert doubling_ladder(10, 39) == (10, 20, 39)
    with pytest.raises(ValueError, match="needs >= 3"):
        doubling_ladder(10, 20)
    with pytest.raises(ValueError, match="first"):
        doubling_ladder(0, 40)


def _walk(ladder, curve, model="eq10"):
    """Rung-by-rung verdicts as a strip run takes them; the rung it stops at (None: it never stops)."""
    for k in range(len(ladder)):
        v = ladder_verdict(ladder[: k + 1], curve(np.array(ladder[: k + 1], float)), model)
        if v.stop:
            return ladder[k], v
    return None, v


@pytest.mark.parametrize("B,d,p", [(-0.3e-3 * 60**0.8, 60.0, 0.8), (-2e-3 * 15**2.5, 15.0, 2.5)])
def test_the_ladder_stops_at_the_first_rung_past_2T_and_not_before(B, d, p):
    T = d * eq10_saturation_x(p)
    ladder = doubling_ladder(5, 5120)
    expected = min(n for n in ladder if n >= 2 * T)
    stop, verdict = _walk(ladder, lambda n: eq10_paper(n, B, d, p))
    assert stop == expected, (T, stop)
    assert verdict.saturated and verdict.saturation_shots == pytest.approx(T, rel=1e-4)
    # and the saturation stage's fit of those rungs is not extrapolated: the target velocity accepts it
    rungs = np.array([n for n in ladder if n <= stop], float)
    assert not fit_saturation(rungs, eq10_paper(rungs, B, d, p)).extrapolated


def test_exp2_model_stops_at_the_first_rung_past_its_closed_form_2T():
    a, b = 0.35e-3, 1 / 70.0  # T = ln 10 / b = 161 shots
    ladder = doubling_ladder(10, 5120)
    stop, verdict = _walk(ladder, lambda n: a * -np.expm1(-b * n), "exp2")
    assert stop == 640 and verdict.saturated  # 2T = 322: 320 is one short, 640 the first past it
    assert verdict.saturation_shots == pytest.approx(np.log(10) / b, rel=1e-6)


def test_a_curve_that_never_saturates_runs_to_the_cap_and_says_so():
    ladder = doubling_ladder(10, 1280)
    stop, verdict = _walk(ladder, lambda n: 1e-4 * np.log1p(n))  # +~10-30 % per doubling, forever
    assert stop is None and not verdict.saturated and not verdict.stop


def test_a_saturation_point_below_the_first_rung_stops_at_once_unsaturated():
    a, b = 0.35e-3, 1 / 7.0  # T = 16 shots, below a first rung of 40
    ladder = doubling_ladder(40, 5120)
    stop, verdict = _walk(ladder, lambda n: a * -np.expm1(-b * n), "exp2")
    assert stop == 160 and not verdict.saturated and "first_shots" in verdict.reason


def test_fewer_than_three_rungs_never_stop():
    assert not ladder_verdict([10, 20], [1e-4, 1.5e-4]).stop
