"""Shots (peenflow.fe.shots): their data, the straight free flight to first contact, and the impact-size
estimates' energy balances."""

import math

import numpy as np
import pytest

from peenflow.fe.shots import Shots, hertz, johnson_plastic, time_to_contact

R = 0.29e-3
RHO = 7800.0


def flat(n=11, h=20e-6):
    """A flat surface z = 0 of n x n points, spacing h, centred on the origin."""
    a = (np.arange(n) - n // 2) * h
    X, Y = np.meshgrid(a, a)
    return np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])


def test_mass_inertia_and_validation():
    s = Shots([[0, 0, -1e-3]], [[0, 0, 50.0]], R, RHO)
    assert s.mass == pytest.approx(RHO * 4 / 3 * math.pi * R**3)
    assert s.inertia == pytest.approx(0.4 * s.mass * R**2)  # solid sphere
    assert s.spins.shape == (1, 3) and not s.spins.any()
    with pytest.raises(ValueError, match="both be"):
        Shots([[0, 0, 0]], [[0, 0, 1], [0, 0, 1]], R, RHO)
    with pytest.raises(ValueError, match="positive"):
        Shots([[0, 0, 0]], [[0, 0, 1]], 0.0, RHO)
    with pytest.raises(ValueError, match="spins"):
        Shots([[0, 0, 0]], [[0, 0, 1]], R, RHO, spins=[[1.0, 2.0]])


def test_a_shot_flies_straight_to_its_first_touch():
    xs = flat()
    gap = 7e-6
    # normal: the lowest point of the sphere reaches the node below after gap / v
    t = time_to_contact(xs, np.array([0.0, 0.0, -R - gap]), np.array([0.0, 0.0, 50.0]), R)
    assert t == pytest.approx(gap / 50.0, rel=1e-9)
    # oblique at 60 degrees, aimed at the same point: ballistic, so the time scales with 1 / speed
    u = np.array([math.cos(math.radians(60)), 0.0, math.sin(math.radians(60))])
    c = np.array([0.0, 0.0, -R]) - 30e-6 * u
    t1 = time_to_contact(xs, c, 40.0 * u, R)
    t2 = time_to_contact(xs, c, 80.0 * u, R)
    assert 0 < t1 <= 30e-6 / 40.0 and t2 == pytest.approx(0.5 * t1, rel=1e-12)
    # the sphere is then tangent to the surface: no point inside, at least one on it
    d = np.linalg.norm(xs - (c + 40.0 * u * t1), axis=1)
    assert d.min() == pytest.approx(R, rel=1e-9)


def test_a_raised_node_is_touched_earlier_and_a_shot_flying_away_never():
    xs = flat()
    gap = 7e-6
    centre, vel = np.array([0.0, 0.0, -R - gap]), np.array([0.0, 0.0, 50.0])
    bump = xs.copy()
    bump[len(xs) // 2, 2] = -3e-6  # a 3 um pile-up under the shot
    assert time_to_contact(bump, centre, vel, R) == pytest.approx((gap - 3e-6) / 50.0, rel=1e-9)
    assert time_to_contact(xs, centre, -vel, R) < 0  # its line touched the surface upstream only
    assert time_to_contact(xs, np.array([1e-3, 0.0, -R - gap]), vel, R) == math.inf  # passes beside
    assert time_to_contact(xs, centre, np.zeros(3), R) == math.inf  # at rest


def test_impact_estimates_balance_the_shot_energy():
    m = RHO * 4 / 3 * math.pi * R**3
    v = 55.0
    e = 0.5 * m * v**2
    h = hertz(R, m, v, 205e9, 0.29)
    # Hertz: the elastic work 2/5 F delta at the deepest point is the shot's energy, a^2 = R delta
    assert 0.4 * h["F"] * h["delta"] == pytest.approx(e, rel=1e-12)
    assert h["a"] ** 2 == pytest.approx(R * h["delta"], rel=1e-12)
    p = 3.0 * 1408e6
    j = johnson_plastic(R, m, v, p)
    # constant mean pressure p over pi a^2 = 2 pi R delta: the work pi R p delta^2 is the shot's energy
    assert math.pi * R * p * j["delta"] ** 2 == pytest.approx(e, rel=1e-12)
    assert j["a"] == pytest.approx(math.sqrt(2 * R * j["delta"]), rel=1e-12)
