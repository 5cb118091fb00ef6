"""Adaptive sequences (issue 10 §3): add sequences until the intensity's standard error meets the
tolerance -- stops when it should and not before."""

import math

import numpy as np
import pytest

from scipy.stats import chi2

from peenflow.methods import sequences_verdict


def _walk(stream, tol, n_min=2, n_max=64):
    for k in range(1, len(stream) + 1):
        v = sequences_verdict(stream[:k], tol, n_min, n_max)
        if v.stop:
            return k, v
    return None, v


def test_a_hand_computed_stream_stops_where_the_95_percent_bound_meets_the_tolerance():
    # [0.300, 0.310, 0.305]: s = 0.0050, SE = 0.00289, bound = s sqrt(2 / chi2(0.05, 2)) / sqrt(3) = 0.01275
    three = [0.300, 0.310, 0.305]
    bound = 0.005 * math.sqrt(2 / chi2.ppf(0.05, 2)) / math.sqrt(3)
    assert bound == pytest.approx(0.01275, rel=1e-3)
    v = sequences_verdict(three, 0.013)
    assert v.met and v.standard_error == pytest.approx(0.005 / math.sqrt(3), rel=1e-9)
    assert v.bound == pytest.approx(bound, rel=1e-9)
    assert not sequences_verdict(three, 0.0127).stop  # not before: the bound 0.01275 is above it
    assert not sequences_verdict(three[:2], 0.013).stop  # two: SE 0.005, but the bound is 16 s / sqrt(2)
    assert not sequences_verdict([0.300], 1.0).stop  # one sequence has no spread, whatever the tolerance


def test_never_fewer_than_n_min_even_when_two_agree_exactly():
    assert not sequences_verdict([0.3, 0.3], 1e-3, n_min=3).stop
    assert sequences_verdict([0.3, 0.3, 0.3], 1e-3, n_min=3).met


def test_the_cap_stops_an_unmet_tolerance_and_says_how_many_would_do():
    v = sequences_verdict([0.28, 0.32, 0.30, 0.26], 0.001, n_max=4)
    assert v.stop and not v.met
    s = np.std([0.28, 0.32, 0.30, 0.26], ddof=1)
    assert v.needed == math.ceil((s / 0.001) ** 2) and "cap" in v.reason


def test_a_failed_sequence_counts_as_run_but_gives_no_spread():
    v = sequences_verdict([0.30, np.nan], 0.1, n_max=2)
    assert v.stop and not v.met  # the cap is reached with one intensity: no standard error to meet


def test_stopping_counts_follow_the_spread_over_many_random_points():
    """With intensities of spread sigma, the points' mean intensities are within the tolerance (RMS error
    over 400 random points <= tol) and they stop not before (sigma / tol)^2 sequences in the median, nor
    wastefully late (median < 2 (sigma / tol)^2).  (Stopping on s / sqrt(n) itself failed this: median
    11 against 17.4, the early stops by chance agreement; an 84 % bound left the RMS error 1.24 tol.)"""
    rng = np.random.default_rng(5)
    sigma, tol = 0.005, 0.0012  # (sigma / tol)^2 = 17.4
    stops, errors = [], []
    for _ in range(400):
        stream = 0.3 + sigma * rng.standard_normal(200)
        n, v = _walk(stream, tol, n_max=200)
        assert v.met
        stops.append(n)
        errors.append(stream[:n].mean() - 0.3)
    assert np.sqrt(np.mean(np.square(errors))) <= tol
    assert (sigma / tol) ** 2 <= np.median(stops) < 2 * (sigma / tol) ** 2
