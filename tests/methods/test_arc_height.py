"""Arc height, eqs. (6)-(9): analytic profiles and equilibrium of the released stress."""

import numpy as np
import pytest

from peenflow.methods.arc_height import clamping_force_moment, release_strip
from peenflow.methods.residual_profile import DepthProfile, equilibrium_residual
from peenflow.testing import SAE1070

E = SAE1070["E"]  # paper Table 1
B, H = 19e-3, 1.29e-3  # type A strip
GAUGE_SPAN = 31.75e-3  # SAE J442 (the library's strips.A.gauge_span_mm)


def test_uniform_stress_only_stretches():
    # A uniform stress has no moment about the mid-plane: no curvature, no arc height.
    s = -300e6
    prof = DepthProfile(np.linspace(0, H, 11), np.full(10, s), "layers")
    rel = release_strip(prof, B, H, E, GAUGE_SPAN)
    assert rel.force == pytest.approx(s * B * H, rel=1e-12)
    assert abs(rel.moment) < 1e-12 * abs(s) * B * H**2
    assert abs(rel.arc_height) < 1e-15
    assert np.allclose(rel.released.values, 0.0, atol=1e-6)


def test_linear_profile_hand_formula():
    # σ = -s (1 - z/h): F = -s b h / 2, M = b s h^2 / 12 (hand integral), so
    # Ah = 3 M l^2 / (2 E b h^3) = s l^2 / (8 E h).
    s = 600e6
    z = np.linspace(0, H, 2)
    prof = DepthProfile(z, -s * (1 - z / H), "linear")
    f, m = clamping_force_moment(prof, B, H)
    assert f == pytest.approx(-s * B * H / 2, rel=1e-12)
    assert m == pytest.approx(B * s * H**2 / 12, rel=1e-12)
    ah = release_strip(prof, B, H, E, GAUGE_SPAN).arc_height
    assert ah == pytest.approx(s * GAUGE_SPAN**2 / (8 * E * H), rel=1e-12)
    assert ah > 0  # compressive surface layer: convex towards the peened side


def test_layered_linear_profile_has_known_discretisation_error():
    # Layer averages of σ = -s (1 - z/h) (value at the layer mid-depth) integrate the
    # force exactly; the moment loses b σ' Δ^3/12 per layer, i.e. M = b s (h^2 - Δ^2)/12.
    s, n = 600e6, 8
    edges = np.linspace(0, H, n + 1)
    mid = 0.5 * (edges[1:] + edges[:-1])
    prof = DepthProfile(edges, -s * (1 - mid / H), "layers")
    f, m = clamping_force_moment(prof, B, H)
    d = H / n
    assert f == pytest.approx(-s * B * H / 2, rel=1e-12)
    assert m == pytest.approx(B * s * (H**2 - d**2) / 12, rel=1e-12)


def test_pure_bending_profile_is_fully_released():
    k = 4e11  # Pa/m
    z = np.linspace(0, H, 7)
    prof = DepthProfile(z, k * (z - H / 2), "linear")
    rel = release_strip(prof, B, H, E, GAUGE_SPAN)
    assert abs(rel.force) < 1e-9 * k * B * H**2
    assert rel.curvature == pytest.approx(k / E, rel=1e-12)
    assert np.allclose(rel.released.values, 0.0, atol=1e-9 * k * H)


@pytest.mark.parametrize("kind", ["layers", "linear"])
def test_released_stress_is_self_equilibrated(kind):
    # A peening-like profile: compressive skin, tensile core, arbitrary layers.
    edges = np.concatenate([np.linspace(0, 0.3e-3, 13), np.linspace(0.3e-3, H, 9)[1:]])
    if kind == "layers":
        zc = 0.5 * (edges[1:] + edges[:-1])
        prof = DepthProfile(edges, -700e6 * np.exp(-zc / 0.1e-3) + 150e6 * np.sin(zc / H * 3), "layers")
    else:
        prof = DepthProfile(edges, -700e6 * np.exp(-edges / 0.1e-3) + 150e6 * np.sin(edges / H * 3), "linear")
    before = equilibrium_residual(prof, H)
    assert before.relative_force > 0.05  # the clamped profile is not in equilibrium
    rel = release_strip(prof, B, H, E, GAUGE_SPAN)
    after = equilibrium_residual(rel.released, H)
    assert after.relative_force < 1e-12
    assert after.relative_moment < 1e-12
    # the width cancels in the arc height
    assert release_strip(prof, 2 * B, H, E, GAUGE_SPAN).arc_height == pytest.approx(rel.arc_height, rel=1e-12)


def test_profile_outside_thickness_is_rejected():
    prof = DepthProfile([0, 2 * H], [1e6], "layers")
    with pytest.raises(ValueError, match="outside the thickness"):
        release_strip(prof, B, H, E, GAUGE_SPAN)
