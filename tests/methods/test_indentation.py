"""Dent ellipse on analytic dents with a known pile-up crest."""

import numpy as np
import pytest

from peenflow.methods.indentation import dent_ellipse

H = 25e-6  # grid spacing, the paper's fine mesh (§5)
X = np.arange(-1.2e-3, 1.2e-3 + H / 2, H)
Y = np.arange(-1.0e-3, 1.0e-3 + H / 2, H * 1.2)  # different spacing in y


def synthetic(cx, cy, a, b, xd=None, depth=20e-6, pile=5e-6, w=0.15, cap=0.5):
    """Cap centred at (xd, cy) plus a Gaussian rim at normalised radius 1 of the ellipse.

    The cap vanishes (value and slope) well inside the rim, so the lowest point of
    uz along any ray from inside the ellipse is exactly on the ellipse: ρ(t) is convex
    and crosses 1 once, where the rim term is minimal.
    """
    xd = cx if xd is None else xd
    XX, YY = np.meshgrid(X, Y, indexing="ij")
    rho = np.hypot((XX - cx) / a, (YY - cy) / b)
    rd = np.hypot((XX - xd) / a, (YY - cy) / b) / cap
    return depth * np.clip(1 - rd**2, 0, None) ** 2 - pile * np.exp(-((rho - 1) ** 2) / (2 * w**2))


def test_circular_dent_of_normal_impact():
    r0 = 0.3e-3
    uz = synthetic(0.0, 0.0, r0, r0)
    e = dent_ellipse(X, Y, uz)
    assert e.semi_axis_along == pytest.approx(r0, abs=0.02 * H)
    assert e.semi_axis_across == pytest.approx(r0, abs=0.02 * H)
    assert abs(e.centre_x) < 0.02 * H and abs(e.centre_y) < 0.02 * H
    assert e.depth == pytest.approx(20e-6, rel=1e-3)
    assert e.pileup_height == pytest.approx(5e-6, rel=1e-2)
    assert e.area == pytest.approx(np.pi * r0**2, rel=1e-3)


def test_elongated_oblique_dent_centre_shifts_from_impact_point():
    # ellipse centred downstream (+x) of the impact point, deepest point upstream of centre
    a, b, cx = 0.36e-3, 0.26e-3, 0.07e-3
    uz = synthetic(cx, 0.0, a, b, xd=cx - 0.06e-3)
    e = dent_ellipse(X, Y, uz, impact_point=(0.0, 0.0))
    assert e.semi_axis_along == pytest.approx(a, abs=0.02 * H)
    assert e.semi_axis_across == pytest.approx(b, abs=0.02 * H)
    assert e.offset[0] == pytest.approx(cx, abs=0.02 * H)
    assert abs(e.offset[1]) < 0.02 * H


def test_noisy_mesh_within_a_fraction_of_the_grid_spacing():
    # noise of 4 % of the pile-up height on every node; smoothing spline told the noise level.
    # Required: a quarter of the grid spacing (sub-grid crest location despite the noise).
    a, b = 0.34e-3, 0.28e-3
    rng = np.random.default_rng(0)
    uz = synthetic(0.02e-3, -0.01e-3, a, b) + 0.2e-6 * rng.standard_normal((X.size, Y.size))
    e = dent_ellipse(X, Y, uz, noise=0.2e-6)
    assert e.semi_axis_along == pytest.approx(a, abs=0.25 * H)
    assert e.semi_axis_across == pytest.approx(b, abs=0.25 * H)
    assert e.centre_x == pytest.approx(0.02e-3, abs=0.25 * H)
    assert e.centre_y == pytest.approx(-0.01e-3, abs=0.25 * H)


def test_edge_rim_finds_zero_crossing_of_a_sink_in_dent():
    # smooth paraboloid dent uz = d (1 - r²/rc²) with no pile-up: it crosses 0 at rc and
    # keeps falling to the grid edge, so no crest exists inside the grid.
    rc = 0.25e-3
    XX, YY = np.meshgrid(X, Y, indexing="ij")
    uz = 20e-6 * (1 - (XX**2 + YY**2) / rc**2)
    with pytest.raises(ValueError, match="rim='edge'"):
        dent_ellipse(X, Y, uz)
    # a dent clipped at zero (kinked edge): spline overshoot must not be taken for a pile-up
    with pytest.raises(ValueError, match="rim='edge'"):
        dent_ellipse(X, Y, np.clip(uz, 0, None))
    e = dent_ellipse(X, Y, uz, rim="edge")
    assert e.semi_axis_along == pytest.approx(rc, abs=0.02 * H)
    assert e.semi_axis_across == pytest.approx(rc, abs=0.02 * H)
    assert e.pileup_height == 0.0


def test_bad_input_shapes_raise():
    with pytest.raises(ValueError):
        dent_ellipse(X, Y, np.zeros((Y.size, X.size)))
