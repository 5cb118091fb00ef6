"""Structured hexahedral mesh: grading, numbering, masses."""

import numpy as np
import pytest

from peenflow.fe.mesh import MAX_GRADING_RATIO, BoxMesh, graded_axis, graded_box


def test_graded_axis_fine_zone_then_ratio_at_most_1_2():
    a = graded_axis(0.3e-3, 25e-6, 1.29e-3, 1.2)
    d = np.diff(a)
    assert a[0] == 0.0 and a[-1] == pytest.approx(1.29e-3, rel=1e-12)
    np.testing.assert_allclose(d[:12], 25e-6, rtol=1e-12)
    growth = d[1:] / d[:-1]
    assert np.all(growth <= 1.2 + 1e-9) and np.all(growth >= 1.0 - 1e-9)


def test_uniform_when_fine_zone_covers_all():
    a = graded_axis(1e-3, 1e-4, 1e-3)
    np.testing.assert_allclose(np.diff(a), 1e-4, rtol=1e-9)


def test_rejects_steep_grading():
    with pytest.raises(ValueError, match="ratio = 1.6"):
        graded_axis(1e-4, 1e-5, 1e-3, ratio=1.6)


def test_steeper_grading_up_to_the_bound():
    # a reference mesh's far field: 1.5 is accepted, the ratio holds and the axis ends exactly
    a = graded_axis(0.1e-3, 6.25e-6, 2.0e-3, MAX_GRADING_RATIO)
    d = np.diff(a)
    assert a[-1] == pytest.approx(2.0e-3, rel=1e-12)
    growth = d[1:] / d[:-1]
    assert np.all(growth <= MAX_GRADING_RATIO + 1e-9) and np.all(growth >= 1.0 - 1e-9)
    assert growth.max() > 1.4  # the steep ratio is actually used
    assert len(d) < len(np.diff(graded_axis(0.1e-3, 6.25e-6, 2.0e-3, 1.2)))


def test_largest_element_cap():
    a = graded_axis(0.3e-3, 25e-6, 1.29e-3, 1.2, h_max=60e-6)
    d = np.diff(a)
    assert a[-1] == pytest.approx(1.29e-3, rel=1e-12)
    assert d.max() <= 60e-6 * (1 + 1e-9)
    assert d.max() >= 0.95 * 60e-6  # the cap is reached, the far elements are at it
    growth = d[1:] / d[:-1]
    assert np.all(growth <= 1.2 + 1e-9) and np.all(growth >= 1.0 - 1e-9)
    # without the cap the deep elements are far larger
    assert np.diff(graded_axis(0.3e-3, 25e-6, 1.29e-3, 1.2)).max() > 100e-6
    with pytest.raises(ValueError, match="h_max"):
        graded_axis(0.3e-3, 25e-6, 1.29e-3, 1.2, h_max=20e-6)


def test_numbering_mass_and_volume():
    m = graded_box(0.2e-3, 0.15e-3, 25e-6, fine_half_width=0.05e-3, fine_depth=0.05e-3)
    nx, ny, nz = m.shape_elements
    conn = m.connectivity()
    X = m.node_coordinates()
    # element e = i + nx (j + ny k) has its first node at (i, j, k) and positive orientation
    e = 3 + nx * (2 + ny * 1)
    assert np.allclose(X[conn[e, 0]], [m.x[3], m.y[2], m.z[1]])
    assert np.allclose(X[conn[e, 6]], [m.x[4], m.y[3], m.z[2]])
    vol = m.element_volumes()
    assert vol.sum() == pytest.approx(0.4e-3 * 0.4e-3 * 0.15e-3, rel=1e-12)
    assert m.lumped_mass(7800.0).sum() == pytest.approx(7800.0 * vol.sum(), rel=1e-12)
    np.testing.assert_allclose(m.element_centroids()[e], X[conn[e]].mean(axis=0))
    assert m.surface_tributary_area().sum() == pytest.approx(0.4e-3**2, rel=1e-12)


def test_quarter_model_starts_at_symmetry_planes():
    m = graded_box(0.2e-3, 0.1e-3, 25e-6, quarter=True)
    assert m.x[0] == 0.0 and m.y[0] == 0.0 and m.z[0] == 0.0


def test_rejects_non_monotone_axis():
    with pytest.raises(ValueError):
        BoxMesh(np.array([0.0, 1.0, 0.5]), np.array([0.0, 1.0]), np.array([0.0, 1.0]))
