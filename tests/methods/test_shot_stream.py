"""Shot streams: reproducibility, 2R rule, uniform landing, arrival order, ladder."""

import numpy as np
import pytest
from scipy.spatial.distance import pdist
from scipy.stats import kstest

from peenflow.methods.shot_stream import generate_centres, impingement_direction, shot_stream

R = 0.29e-3  # S230
A = 3 * 0.58e-3  # 6D × 6D strip REV: a = b = 3D


def test_same_seed_same_stream_different_seed_different():
    s1 = shot_stream(200, R, A, A, 45.0, 55.0, seed=3)
    s2 = shot_stream(200, R, A, A, 45.0, 55.0, seed=3)
    s3 = shot_stream(200, R, A, A, 45.0, 55.0, seed=4)
    for f in ("centres", "velocities", "landing", "arrival_time", "generation_index"):
        assert np.array_equal(getattr(s1, f), getattr(s2, f))
    assert not np.allclose(s1.landing, s3.landing)


def test_minimum_distance_2R_is_respected_when_rejections_happen():
    # small surface, many shots: the 2R rule must be active and obeyed
    s = shot_stream(300, R, 2 * R, 2 * R, 90.0, 50.0, seed=1)
    assert s.n_rejected > 0
    assert pdist(s.centres).min() >= 2 * R * (1 - 1e-12)


def test_infeasible_packing_raises():
    with pytest.raises(ValueError, match="too small"):
        generate_centres(50, R, 0.1 * R, 0.1 * R, 90.0, seed=0, max_attempts_per_shot=20)


def test_eq2_ranges_and_normal_velocity():
    n = 150
    s = shot_stream(n, R, A, 0.5 * A, 90.0, 40.0, seed=2)
    z = s.centres[:, 2]
    assert np.all(z <= -R) and np.all(z >= -R * (2 * n - 1))
    assert np.all(np.abs(s.centres[:, 0]) <= A) and np.all(np.abs(s.centres[:, 1]) <= 0.5 * A)
    assert np.all(s.velocities[:, :2] == 0.0)
    assert np.allclose(s.velocities[:, 2], 40.0)
    np.testing.assert_array_equal(s.landing, s.centres[:, :2])


@pytest.mark.parametrize("angle", [45.0, 67.5])
def test_oblique_kinematics_are_consistent(angle):
    s = shot_stream(100, R, A, A, angle, 55.0, seed=5)
    u = impingement_direction(angle)
    assert u[0] > 0 and u[2] > 0  # travels towards +x, +z
    assert np.allclose(np.linalg.norm(s.velocities, axis=1), 55.0)
    # moving each centre for its arrival time puts it at z = -R above its landing point
    at = s.centres + s.velocities * s.arrival_time[:, None]
    np.testing.assert_allclose(at[:, 2], -R, atol=1e-12)
    np.testing.assert_allclose(at[:, :2], s.landing, atol=1e-12)
    assert np.all(np.diff(s.arrival_time) >= 0)


def test_landing_uniform_for_oblique_impacts_and_printed_eq3_is_shifted():
    # KS test of landing x against U[-a, a]. With n = 2000 the printed eq. (3) shifts
    # landings by 2R/tan45 = 2R, i.e. 1/6 of the width: KS distance ≈ 0.167, far above
    # the 0.1 % critical value 1.95/sqrt(2000) ≈ 0.044. The fixed seed makes it deterministic.
    n, a = 2000, 6 * R
    s = shot_stream(n, R, a, a, 45.0, 55.0, seed=11)
    ux = (s.landing[:, 0] + a) / (2 * a)
    uy = (s.landing[:, 1] + a) / (2 * a)
    assert kstest(ux, "uniform").pvalue > 1e-3
    assert kstest(uy, "uniform").pvalue > 1e-3
    assert np.all(np.abs(s.landing) <= a * (1 + 1e-12))
    lit = shot_stream(n, R, a, a, 45.0, 55.0, seed=11, literal_eq3=True)
    np.testing.assert_allclose(lit.landing[:, 0].max() - a, -2 * R, atol=0.05 * a)
    assert kstest((lit.landing[:, 0] + a) / (2 * a), "uniform").pvalue < 1e-6


def test_first_n_is_arrival_prefix_and_a_valid_stream():
    nmax, n = 480, 100
    s = shot_stream(nmax, R, A, A, 45.0, 55.0, seed=8)
    f = s.first(n)
    assert f.n_shots == n
    np.testing.assert_array_equal(f.centres, s.centres[:n])
    assert f.arrival_time.max() <= s.arrival_time[n:].min()
    assert pdist(f.centres).min() >= 2 * R * (1 - 1e-12)
    # nested ladder
    np.testing.assert_array_equal(s.first(40).landing, f.landing[:40])
    # the n-th arrival sits at a column depth following the Beta(n, nmax+1-n) order statistic
    L = 2 * R * (nmax - 1)
    depth_n = -R - f.centres[-1, 2]  # height of the n-th arrival above the first possible one
    mean = L * n / (nmax + 1)
    sd = L * np.sqrt(n * (nmax + 1 - n) / ((nmax + 1) ** 2 * (nmax + 2)))
    assert abs(depth_n - mean) < 4 * sd
    # landings of the first n are still uniform
    assert kstest((f.landing[:, 0] + A) / (2 * A), "uniform").pvalue > 1e-3
