"""Shot streams with size and speed spreads: reproducible, the stated moments, the paper's stream without them."""

import math

import numpy as np
import pytest
from scipy.spatial.distance import pdist, squareform
from scipy.stats import kstest, truncnorm

from peenflow.methods.shot_stream import (TRUNCATED_STD_FACTOR, largest_factor, shot_stream, spread_factors)

R = 0.29e-3  # S230
A = 12 * R
FIELDS = ("centres", "velocities", "landing", "arrival_time", "generation_index", "radii", "speeds")


def test_no_spread_is_the_papers_stream_bit_for_bit():
    plain = shot_stream(300, R, A, A, 45.0, 55.0, seed=3)
    zero = shot_stream(300, R, A, A, 45.0, 55.0, seed=3, diameter_spread=0.0, velocity_spread=0.0)
    for f in FIELDS:
        assert np.array_equal(getattr(plain, f), getattr(zero, f)), f
    assert not plain.spread and np.all(plain.radii == R) and np.all(plain.speeds == 55.0)


def test_the_truncation_constant_is_the_truncated_normals_standard_deviation():
    assert TRUNCATED_STD_FACTOR == pytest.approx(truncnorm.std(-3, 3), rel=1e-9)
    assert largest_factor(0.1) == pytest.approx(1 + 0.3 / truncnorm.std(-3, 3), rel=1e-9)  # the constant has 10 digits


def test_factors_have_the_stated_mean_and_standard_deviation():
    n, spread = 40_000, 0.10
    f = spread_factors(n, spread, np.random.Generator(np.random.PCG64(7)))
    # standard errors: of the mean spread / sqrt(n), of the std about spread / sqrt(2 n) (near-normal)
    assert abs(f.mean() - 1.0) < 4 * spread / math.sqrt(n)
    assert abs(f.std() - spread) < 4 * spread / math.sqrt(2 * n)
    assert f.min() >= 2.0 - largest_factor(spread) and f.max() <= largest_factor(spread)
    # the shape: a normal truncated at +-3 of its sigma
    assert kstest((f - 1.0) / (spread / TRUNCATED_STD_FACTOR), truncnorm(-3, 3).cdf).pvalue > 1e-3


def test_a_spread_stream_is_reproducible_and_its_seed_matters():
    kw = dict(diameter_spread=0.1, velocity_spread=0.05)
    a = shot_stream(200, R, A, A, 60.0, 50.0, seed=5, **kw)
    b = shot_stream(200, R, A, A, 60.0, 50.0, seed=5, **kw)
    c = shot_stream(200, R, A, A, 60.0, 50.0, seed=6, **kw)
    for f in FIELDS:
        assert np.array_equal(getattr(a, f), getattr(b, f)), f
    assert not np.allclose(a.radii, c.radii) and not np.allclose(a.speeds, c.speeds)


def test_each_shot_flies_at_its_own_speed_lands_uniformly_and_keeps_clear_of_the_others():
    n = 2000
    s = shot_stream(n, R, A, A, 45.0, 55.0, seed=11, diameter_spread=0.1, velocity_spread=0.08)
    u = np.array([math.cos(math.radians(45.0)), 0.0, math.sin(math.radians(45.0))])
    np.testing.assert_allclose(s.velocities, s.speeds[:, None] * u, rtol=0, atol=1e-12)
    assert abs(s.radii.std() / R - 0.1) < 4 * 0.1 / math.sqrt(2 * n)
    assert abs(s.speeds.std() / 55.0 - 0.08) < 4 * 0.08 / math.sqrt(2 * n)
    # sorted by arrival at each shot's own speed: t = path / speed, path to z = -R_i
    t = (-s.radii - s.centres[:, 2]) / u[2] / s.speeds
    np.testing.assert_allclose(s.arrival_time, t, rtol=1e-12)
    assert np.all(np.diff(s.arrival_time) >= 0)
    # a shot of radius R_i still touches z = 0 over a uniform landing point (eq. 3 with its own R)
    for k in (0, 1):
        assert kstest((s.landing[:, k] + A) / (2 * A), "uniform").pvalue > 1e-3
    # no two initial spheres overlap: R_i + R_j apart
    d = squareform(pdist(s.centres))
    np.fill_diagonal(d, np.inf)
    assert np.all(d >= (s.radii[:, None] + s.radii[None, :]) * (1 - 1e-12))


def test_the_first_n_arrivals_keep_their_own_sizes_and_speeds():
    s = shot_stream(400, R, A, A, 45.0, 55.0, seed=8, diameter_spread=0.1, velocity_spread=0.05)
    f = s.first(100)
    assert np.array_equal(f.radii, s.radii[:100]) and np.array_equal(f.speeds, s.speeds[:100])
    assert f.spread and f.diameter_spread == 0.1


def test_a_spread_that_could_draw_a_non_positive_shot_is_refused():
    with pytest.raises(ValueError, match="every factor is positive"):
        spread_factors(10, 0.34, np.random.Generator(np.random.PCG64(0)))
