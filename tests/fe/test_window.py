"""The active window (peenflow.fe.window): its size rule, the box it integrates, its validity, the
absorbing sponge, and the viscous-spring faces' coefficients."""

import math

import numpy as np
import pytest

from peenflow.fe.impact import Options
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.model import Model, Target
from peenflow.fe.shots import Shots, hertz
from peenflow.fe.window import (WINDOW_VALIDATED, contact_estimates, impact_window, sponge, viscous_spring_boundary,
                                window_size, window_validity)

R = 0.29e-3
SAE1070 = dict(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
MAT = Material(**SAE1070)
H = 25e-6


def uniform(n=64, lateral="symmetric", nz=24):
    ax = np.linspace(-0.5 * n * H, 0.5 * n * H, n + 1)
    return Model(Target(BoxMesh(ax, ax.copy(), np.linspace(0.0, nz * H, nz + 1)), lateral=lateral), MAT)


def shot():
    return Shots([[0.0, 0.0, -R - 1e-6]], [[0.0, 0.0, 55.0]], R, 7800.0)


def test_contact_estimates_are_at_least_hertz():
    """The window is sized on the larger of the elastic (Hertz) and fully plastic (mean pressure 3 A) contact."""
    s = shot()
    a, t = contact_estimates(s, MAT, 55.0)
    h = hertz(R, s.mass, 55.0, MAT.E, MAT.nu)
    assert a >= h["a"] and t >= h["t"]
    # fully plastic radius: the shot's energy spent on pressure 3 A over the dent, pi a^4 / (4 R) * 3 A
    assert a == pytest.approx((4.0 * R * 0.5 * s.mass * 55.0**2 / (math.pi * 3.0 * MAT.A)) ** 0.25, rel=1e-9)


def test_window_size_is_the_largest_of_its_three_rules():
    m = uniform()
    s = shot()
    a, t = contact_estimates(s, MAT, 55.0)
    lat, _, depth = window_size(m, MAT, Options(), a, t, 0.0, 0.0)
    assert lat == pytest.approx(4.0 * a) and depth == pytest.approx(4.0 * a)  # contact radii rule
    lat, _, depth = window_size(m, MAT, Options(window_min_elements=20), a, t, 0.0, 0.0)
    assert lat == pytest.approx(20 * H) and depth == pytest.approx(20 * H)  # element rule
    lat, _, depth = window_size(m, MAT, Options(window_min_wave=1.0), a, t, 0.0, 0.0)
    assert lat == pytest.approx(MAT.wave_speed * t) == depth  # wave-travel rule


def test_impact_window_extends_downstream_and_spans_a_periodic_seam():
    m = uniform()
    s = shot()
    a, t = contact_estimates(s, MAT, 55.0)
    normal = impact_window(m, MAT, Options(), a, t, np.zeros(2), np.array([0.0, 0.0, 55.0]))
    oblique = impact_window(m, MAT, Options(), a, t, np.zeros(2), np.array([30.0, 0.0, 55.0]))
    assert oblique[0] == normal[0] and oblique[1] > normal[1]  # longer only downstream (+x)
    assert tuple(oblique[2:]) == tuple(normal[2:])
    assert tuple(impact_window(m, MAT, Options(window=False), a, t, np.zeros(2), np.zeros(3))) == (0, 64, 0, 64, 0, 24)
    p = uniform(lateral="periodic")
    near_seam = impact_window(p, MAT, Options(), a, t, np.array([0.75e-3, 0.0]), np.array([0.0, 0.0, 55.0]))
    assert (near_seam[0], near_seam[1]) == (0, 64) and near_seam[2] > 0  # spans x only


def test_window_validity_counts_elements_and_wave_travel():
    m = uniform()
    s = shot()
    a, t = contact_estimates(s, MAT, 55.0)
    n = int(WINDOW_VALIDATED["elements"])
    wide = np.array([32 - n, 32 + n, 32 - n, 32 + n, 0, n])  # held faces exactly n elements away
    assert window_validity(m, MAT, wide, 0.0, 0.0, t) is None
    narrow = wide + np.array([1, -1, 0, 0, 0, 0])
    why = window_validity(m, MAT, narrow, 0.0, 0.0, t)
    assert why is not None and f"{n - 1:.1f} elements" in why
    assert window_validity(m, MAT, m.full_window, 0.0, 0.0, t) is None  # no held face


def test_sponge_layers():
    m = uniform()
    win = np.array([16, 48, 16, 48, 0, 16])
    assert sponge(m, MAT, Options(), win) == (0, 0.0)
    n, rate = sponge(m, MAT, Options(window_sponge=0.25), win)
    assert n == 4  # a quarter of the 16-element half width / depth
    assert rate == pytest.approx(10.0 * MAT.wave_speed / (4 * H))


def test_viscous_spring_coefficients():
    """Dashpots rho c per tributary face area; springs alpha G / R (+ the slab M / e in front of a held mesh face)."""
    h = 50e-6
    ax = np.linspace(-1e-3, 1e-3, 41)
    mesh = BoxMesh(ax, ax.copy(), np.linspace(0.0, 1e-3, 21))
    mat = Material(**SAE1070)
    m = Model(Target(mesh), mat)
    win = np.array([10, 30, 10, 30, 0, 10])
    cp, cs, G, rho = mat.wave_speed, np.sqrt(mat.mu / mat.density), mat.mu, mat.density
    b0 = viscous_spring_boundary(m, win, (0.0, 0.0), slab=0.0)
    # every node of the 4 lateral faces and the bottom, each once
    assert len(b0.nodes) == len(np.unique(b0.nodes)) == 21 * 21 * 11 - 19 * 19 * 10
    bottom, side = 1e-3 * 1e-3, 1e-3 * 0.5e-3
    assert b0.damping[:, 2].sum() == pytest.approx(rho * (cp * bottom + cs * 4 * side))
    assert b0.damping[:, 0].sum() == pytest.approx(rho * (cp * 2 * side + cs * (2 * side + bottom)))
    # the node under the impact point on the bottom face: R = 0.5 mm, A = h^2, e = 0.5 mm to the fixed bottom
    n = 20 + 41 * (20 + 41 * 10)
    q = int(np.nonzero(b0.nodes == n)[0][0])
    assert b0.stiffness[q, 2] == pytest.approx(4 / 3 * G / 0.5e-3 * h * h)
    assert b0.stiffness[q, 0] == pytest.approx(2 / 3 * G / 0.5e-3 * h * h)
    b1 = viscous_spring_boundary(m, win, (0.0, 0.0))
    assert b1.stiffness[q, 2] == pytest.approx((4 / 3 * G / 0.5e-3 + rho * cp * cp / 0.5e-3) * h * h)
    assert b1.stiffness[q, 0] == pytest.approx((2 / 3 * G / 0.5e-3 + G / 0.5e-3) * h * h)
    assert viscous_spring_boundary(m, m.full_window, (0.0, 0.0)) is None
    # face nodes touching an element that has yielded stay held
    ep = np.zeros(mesh.n_elements)
    ep[20 + 40 * (20 + 40 * 9)] = 1e-3  # element just above the bottom face, under the impact point
    b2 = viscous_spring_boundary(m, win, (0.0, 0.0), eps_p=ep)
    assert len(b2.nodes) == len(b0.nodes) - 4 and n not in b2.nodes


def test_every_shot_records_whether_its_window_was_validated():
    from peenflow.fe.impact import ImpactRun

    m = uniform(40, nz=20)
    shots = Shots([[0.0, 0.0, -R - 1e-6], [50e-6, 0.0, -R - 1e-6]], [[0.0, 0.0, 20.0]] * 2, R, 7800.0)
    small = ImpactRun(m.target, MAT, Options(window_warning=False))
    recs = [small.impact(shots, i) for i in range(2)]
    assert [r.window_validated for r in recs] == [False, False]  # ~10 elements to the held faces
    assert small.window_note.startswith("shot 0:")  # the note names the first only
    big = ImpactRun(m.target, MAT, Options(window_min_elements=WINDOW_VALIDATED["elements"]))
    assert big.impact(shots, 0).window_validated and big.window_note == ""
