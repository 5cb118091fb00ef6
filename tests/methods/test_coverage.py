"""Coverage Monte Carlo vs brute force and the closed form; Avrami fit."""

import time

import numpy as np
import pytest

from peenflow.methods import coverage as C
from peenflow.methods.indentation import DentEllipse
from peenflow.methods.shot_stream import shot_stream

D = 0.58e-3
R = D / 2


def dent(a, b=None, dx=0.0, dy=0.0):
    b = a if b is None else b
    return DentEllipse(dx, dy, 0.0, 0.0, a, b, 10e-6, 2e-6)


def test_first_cover_index_matches_brute_force():
    rng = np.random.default_rng(1)
    gx, gy = C.measuring_grid((-1e-3, 1e-3, -0.8e-3, 0.8e-3), 41, 33)
    land = rng.uniform(-1.3e-3, 1.3e-3, size=(25, 2))
    e = dent(0.3e-3, 0.2e-3, dx=0.05e-3, dy=-0.02e-3)
    first = C.first_cover_index(land, e, gx, gy)
    X, Y = np.meshgrid(gx, gy, indexing="ij")
    inside = (((X[None] - land[:, 0, None, None] - 0.05e-3) / 0.3e-3) ** 2
              + ((Y[None] - land[:, 1, None, None] + 0.02e-3) / 0.2e-3) ** 2) <= 1
    expected = np.where(inside.any(0), inside.argmax(0), 25)
    np.testing.assert_array_equal(first, expected)
    assert C.coverage_percent(land, e, gx, gy) == pytest.approx(100 * inside.any(0).mean())
    # the curve is the coverage of the first N landings
    counts = [0, 1, 5, 12, 25]
    curve = C.coverage_curve(land, e, gx, gy, counts)
    for c, n in zip(curve, counts):
        assert c == pytest.approx(100 * inside[:n].any(0).mean() if n else 0.0)


@pytest.mark.parametrize("angle,offset", [(90.0, 0.0), (45.0, 0.06e-3)])
def test_monte_carlo_matches_closed_form(angle, offset):
    # Strip-like REV: peening surface 3 d × 3 d, measuring surface d × d at the centre
    # (d = d_min = 2D). Dent radius 0.25 mm (+ shift of the oblique ellipse) keeps every
    # node's covering region inside the peening surface, as the closed form requires.
    dmin = 2 * D
    a = 1.5 * dmin
    e = dent(0.25e-3, 0.2e-3, dx=offset)
    gx, gy = C.measuring_grid((-dmin / 2, dmin / 2, -dmin / 2, dmin / 2), 60)
    counts = np.array([5, 20, 60, 150])
    n_seq = 100
    streams = [shot_stream(150, R, a, a, angle, 50.0, seed=s).landing for s in range(n_seq)]
    curves = C.coverage_curves(streams, e, gx, gy, counts)
    expected = C.expected_coverage_uniform(counts, e.area, (2 * a) ** 2)
    # Each node is a point covered by one dent with probability A_dent/A_peen exactly, so the
    # closed form has no grid-discretisation bias. t-test across independent sequences at 4
    # standard errors (nodes within one sequence are correlated, so the spread across
    # sequences is the honest error). The 2R rule makes landings slightly non-independent;
    # its effect (measured < 1 %) is within this tolerance.
    mean, se = curves.mean(0), curves.std(0, ddof=1) / np.sqrt(n_seq)
    assert np.all(np.abs(mean - expected) < 4 * se)
    assert np.all(np.diff(curves, axis=1) >= 0)


def test_iid_landings_on_a_large_surface_match_closed_form_tightly():
    # 10 × 10 mm peening surface, 8 × 8 mm measuring grid: ~300 dent areas of independent
    # nodes per sequence, so 10 sequences pin the mean coverage to a fraction of a percent.
    rng = np.random.default_rng(12)
    a = 5e-3
    e = dent(0.25e-3, 0.2e-3, dx=0.04e-3)
    gx, gy = C.measuring_grid((-4e-3, 4e-3, -4e-3, 4e-3), 161)
    counts = np.array([100, 400, 1000, 2000])
    curves = C.coverage_curves([rng.uniform(-a, a, (2000, 2)) for _ in range(10)], e, gx, gy, counts)
    expected = C.expected_coverage_uniform(counts, e.area, (2 * a) ** 2)
    se = curves.std(0, ddof=1) / np.sqrt(10)
    assert np.all(se < 1.0)  # a test with teeth: a 4 % coverage error would fail
    assert np.all(np.abs(curves.mean(0) - expected) < 4 * se)


def test_avrami_recovers_closed_form_rate():
    # (1 - q)^N = exp(N ln(1 - q)): eq. (5) with A = -ln(1 - q) exactly
    q = 0.012
    n = np.array([10, 50, 100, 200, 400, 800])
    fit = C.fit_avrami(n, C.expected_coverage_uniform(n, q, 1.0))
    assert fit.rate == pytest.approx(-np.log1p(-q), rel=1e-9)
    assert fit.full_coverage_shots == pytest.approx(np.log(50) / fit.rate, rel=1e-12)
    assert fit.shots_for_coverage(200) == pytest.approx(2 * fit.full_coverage_shots)
    assert fit.shots_for_coverage(50) == pytest.approx(np.log(2) / fit.rate)
    assert fit.shots_for_coverage(99) == fit.full_coverage_shots
    assert fit.coverage_at(fit.full_coverage_shots) == pytest.approx(98.0)
    # a study that calls 95 % full coverage: N_f = ln(20) / A, and 96 % is already "full"
    fit95 = C.fit_avrami(n, C.expected_coverage_uniform(n, q, 1.0), full_percent=95.0)
    assert fit95.full_coverage_shots == pytest.approx(np.log(20) / fit.rate, rel=1e-9)
    assert fit95.shots_for_coverage(96) == fit95.full_coverage_shots
    assert fit95.shots_for_coverage(200) == pytest.approx(2 * np.log(20) / fit.rate, rel=1e-9)


def test_avrami_fit_with_noise_and_saturated_points():
    # points at exactly 100 % (log-linearisation would give inf) are fitted fine
    rng = np.random.default_rng(3)
    A = 0.004
    n = np.array([25, 50, 100, 200, 400, 800, 1600, 3200])
    c = 100 * (1 - np.exp(-A * n)) + rng.normal(0, 1.0, (6, n.size))
    c = np.clip(c, 0, 100)
    fit = C.fit_avrami(n, c)
    # 48 points with 1 % noise: the rate is determined to well within 3 %
    assert fit.rate == pytest.approx(A, rel=0.03)
    assert fit.residual_rms < 1.5


def test_many_dents_large_grid_is_fast():
    rng = np.random.default_rng(0)
    land = rng.uniform(-2.25e-3, 2.25e-3, (3000, 2))
    gx, gy = C.measuring_grid((-0.75e-3, 0.75e-3, -0.75e-3, 0.75e-3), 200)
    t0 = time.perf_counter()
    curve = C.coverage_curve(land, dent(0.15e-3), gx, gy, [500, 1000, 3000])
    assert time.perf_counter() - t0 < 5.0
    assert curve[-1] > curve[0] > 0
