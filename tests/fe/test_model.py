"""The static part of a run (peenflow.fe.model.Model): masses, the window box and its held faces, the
settling damping rate; and the periodic roll it is moved by (peenflow.fe.periodic.roll)."""

import math

import numpy as np
import pytest

from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Model, Target
from peenflow.fe.periodic import roll

MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
H = 50e-6


def mesh(n=10):
    ax = np.linspace(-0.5 * n * H, 0.5 * n * H, n + 1)
    return BoxMesh(ax, ax.copy(), graded_axis(0.15e-3, H, 0.4e-3, 1.2))


def test_lumped_masses_add_up_to_the_body_and_periodic_masters_carry_their_slaves():
    m = mesh()
    body = MAT.density * (m.x[-1] - m.x[0]) * (m.y[-1] - m.y[0]) * m.z[-1]
    sym = Model(Target(m), MAT)
    assert sym.mass.sum() == pytest.approx(body, rel=1e-12) and np.all(sym.mass > 0)
    per = Model(Target(m, lateral="periodic"), MAT)
    assert per.mass.sum() == pytest.approx(body, rel=1e-12)  # moved to the masters, none lost
    slaves = per.masters != np.arange(len(per.mass))
    assert not per.mass[slaves].any()
    # a corner master carries itself, two edge images and the opposite corner: 4 x a corner's mass
    assert per.mass[0] == pytest.approx(4 * sym.mass[0], rel=1e-12)


def test_the_window_box_covers_the_requested_region_and_holds_its_inner_faces():
    mo = Model(Target(mesh(20)), MAT)
    ax = mo.mesh.x
    win = mo.window_box(0.07e-3, -0.12e-3, (0.1e-3, 0.2e-3), (0.15e-3, 0.15e-3), 0.2e-3)
    assert ax[win[0]] <= 0.07e-3 - 0.1e-3 and ax[win[1]] >= 0.07e-3 + 0.2e-3
    assert ax[win[0] + 1] > 0.07e-3 - 0.1e-3 and ax[win[1] - 1] < 0.07e-3 + 0.2e-3  # and no more
    assert mo.mesh.y[win[2]] <= -0.27e-3 and mo.mesh.y[win[3]] >= 0.03e-3 and mo.mesh.z[win[5]] >= 0.2e-3
    assert mo.hold_flags(win).tolist() == [1, 1, 1, 1, 0, 1]  # the top is never held
    edge = mo.window_box(-0.5e-3, 0.0, (0.1e-3, 0.1e-3), (0.1e-3, 0.1e-3), 10.0)
    assert edge[0] == 0 and edge[5] == mo.nz and mo.hold_flags(edge).tolist() == [0, 1, 1, 1, 0, 0]
    assert not mo.hold_flags(mo.full_window).any()


def test_settle_damping_is_near_critical_for_the_slowest_shear_mode():
    mo = Model(Target(mesh()), MAT)
    win = mo.full_window
    L = max(0.5 * (mo.mesh.x[-1] - mo.mesh.x[0]), mo.mesh.z[-1])
    assert mo.settle_alpha(win, 1.0) == pytest.approx(math.pi * math.sqrt(MAT.mu / MAT.density) / L, rel=1e-12)
    assert mo.settle_alpha(win, 2.5) == pytest.approx(2.5 * mo.settle_alpha(win, 1.0), rel=1e-12)


def test_a_roll_moves_the_material_by_whole_elements_and_back():
    mo = Model(Target(mesh(), lateral="periodic"), MAT)
    st = mo.new_state()
    rng = np.random.default_rng(2)
    st.stress[:] = rng.standard_normal(st.stress.shape)
    st.eps_p[:] = rng.random(st.eps_p.shape)
    u = 1e-7 * rng.standard_normal(st.x.shape)
    st.x[:] = mo.nodes0 + u
    before = st.copy()
    roll(mo, st, 3, -2)
    nx, ny, nz = mo.mesh.shape_elements
    s0 = before.stress.reshape(nz, ny, nx, 6)
    s1 = st.stress.reshape(nz, ny, nx, 6)
    # what was at element column i, row j is afterwards at (i - 3) mod nx, (j + 2) mod ny
    np.testing.assert_array_equal(s1, np.roll(s0, (2, -3), axis=(1, 2)))
    np.testing.assert_array_equal(s1[:, 0, 0], s0[:, ny - 2, 3])
    roll(mo, st, -3, 2)
    np.testing.assert_array_equal(st.stress, before.stress)
    np.testing.assert_array_equal(st.eps_p, before.eps_p)
    masters = mo.masters == np.arange(len(mo.masters))
    np.testing.assert_allclose(st.x[masters], before.x[masters], rtol=0, atol=1e-18)
    with pytest.raises(ValueError, match="only a periodic target"):
        roll(Model(Target(mesh()), MAT), st, 1, 0)
