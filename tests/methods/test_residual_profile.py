"""Region averaging per layer, exact profile integrals and the equilibrium helper."""

import numpy as np
import pytest

from peenflow.methods.residual_profile import (
    DepthProfile,
    average_over_region,
    equilibrium_residual,
)


def _structured_mesh(nx=12, ny=10, nz=5, L=1.2e-3, h=0.5e-3):
    xe = np.linspace(-L / 2, L / 2, nx + 1)
    ye = np.linspace(-L / 2, L / 2, ny + 1)
    ze = np.geomspace(20e-6, h, nz)  # graded layers
    ze = np.concatenate([[0.0], ze])
    xc, yc, zc = (0.5 * (e[1:] + e[:-1]) for e in (xe, ye, ze))
    X, Y, Z = np.meshgrid(xc, yc, zc, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]), ze


def test_region_average_recovers_depth_function_and_spread():
    cen, ze = _structured_mesh()
    stress = np.zeros((cen.shape[0], 6))
    c = 5e9  # Pa/m, lateral gradient whose mean over a symmetric region is zero
    stress[:, 0] = -1e12 * cen[:, 2] + c * cen[:, 0]
    stress[:, 5] = 7e6
    region = (-0.3e-3, 0.3e-3, -0.3e-3, 0.3e-3)
    far = np.abs(cen[:, 0]) > 0.3e-3
    stress[far, 0] = 1e12  # outside the region: must not leak into the average
    avg = average_over_region(cen, stress, ze, region)
    zc = 0.5 * (ze[1:] + ze[:-1])
    np.testing.assert_allclose(avg.mean[:, 0], -1e12 * zc, rtol=1e-10)
    np.testing.assert_allclose(avg.mean[:, 5], 7e6, rtol=1e-12)
    sel = (~far) & (np.abs(cen[:, 1]) <= 0.3e-3) & (cen[:, 2] == cen[0, 2])
    expected_std = c * np.sqrt(np.mean(cen[sel, 0] ** 2))
    np.testing.assert_allclose(avg.std[:, 0], expected_std, rtol=1e-8)
    assert np.all(avg.count == sel.sum())
    prof = avg.component("xx")
    assert prof.kind == "layers" and prof.values.shape == (zc.size,)


def test_weights_give_weighted_mean():
    cen = np.array([[0, 0, 1e-6], [1e-6, 0, 1e-6]])
    stress = np.zeros((2, 6))
    stress[:, 0] = [100.0, 200.0]
    avg = average_over_region(cen, stress, [0, 2e-6], (-1, 1, -1, 1), weights=[1.0, 3.0])
    assert avg.mean[0, 0] == pytest.approx(175.0)
    assert avg.std[0, 0] == pytest.approx(np.sqrt((1 * 75**2 + 3 * 25**2) / 4))


def test_empty_layer_raises():
    cen = np.array([[0, 0, 1e-6]])
    with pytest.raises(ValueError, match="no element"):
        average_over_region(cen, np.zeros((1, 6)), [0, 2e-6, 4e-6], (-1, 1, -1, 1))


def test_layers_and_linear_representations_integrate_identically():
    edges = np.array([0.0, 0.1, 0.25, 0.6, 1.0])
    prof = DepthProfile(edges, [3.0, -1.0, 2.0, 0.5], "layers")
    lin = prof.to_linear()
    for origin in (0.0, 0.5, 0.7):
        np.testing.assert_allclose(prof.moments(origin), lin.moments(origin), rtol=1e-13, atol=1e-15)
    # hand value: Σ σ Δz
    assert prof.moments()[0] == pytest.approx(3 * 0.1 - 1 * 0.15 + 2 * 0.35 + 0.5 * 0.4)
    assert prof(0.1) == -1.0  # a boundary takes the deeper layer's value
    assert prof(0.05) == 3.0
    assert np.isnan(prof(1.5))


def test_equilibrium_residual_flags_unbalanced_profiles():
    h = 1.0
    z = np.linspace(0, h, 3)
    assert equilibrium_residual(DepthProfile(z, [1.0, 1.0, 1.0], "linear"), h).relative_force == pytest.approx(1.0)
    bend = equilibrium_residual(DepthProfile(z, [-1.0, 0.0, 1.0], "linear"), h)
    assert bend.relative_force < 1e-15 and bend.relative_moment == pytest.approx(1.0, rel=1e-3)
    # a self-equilibrated cubic-like shape: σ = cos(2π z / h) has zero force and zero moment
    zz = np.linspace(0, h, 2001)
    res = equilibrium_residual(DepthProfile(zz, np.cos(2 * np.pi * zz / h), "linear"), h)
    assert res.is_self_equilibrated(rtol=1e-5)
