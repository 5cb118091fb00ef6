"""The progress of a self-extending strip ladder plans for where eq. (11) says it will stop, not for its cap."""

import math

from tasks._rev_run import expected_end

LADDER = [10, 20, 40, 80, 160, 320, 640, 1280, 2560, 5120]


def test_the_planned_end_is_the_first_rung_at_twice_the_saturation_point():
    assert expected_end(LADDER, 40, 55.0) == 160  # 2 T = 110: the first rung at or beyond it
    assert expected_end(LADDER, 40, 80.0) == 160  # exactly 2 T is enough (eq. 11 needs a rung at >= 2 T)
    assert expected_end(LADDER, 160, 30.0) == 320  # already past 2 T: at least the next rung


def test_without_a_fit_it_plans_one_rung_ahead_and_beyond_the_ladder_the_cap():
    assert expected_end(LADDER, 20, math.nan) == 40
    assert expected_end(LADDER, 640, 4000.0) == 5120
    assert expected_end(LADDER, 5120, 100.0) == 5120
