"""The explicit loop (peenflow.fe.solver.run_phase, through Model.phase): a rigid translation stays a rigid
translation (no stress, exact kinematics), the energy of an undamped elastic vibration is all accounted
for (kinetic + strain + bulk-viscous work), and mass-proportional damping takes it out."""

import numpy as np
import pytest

from peenflow.fe import solver as S
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.model import Model, Target
from peenflow.fe.relaxation import _no_shot

MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
H = 50e-6


def box(n=6, lateral="symmetric", bottom="fixed"):
    ax = np.linspace(0.0, n * H, n + 1)
    return Model(Target(BoxMesh(ax, ax.copy(), ax.copy()), lateral=lateral, bottom=bottom), MAT)


def steps(m, st, n, alpha=0.0):
    """``n`` plain steps over the whole mesh (a "relaxation" that never comes to rest), each recorded."""
    res = m.phase(st, S.MODE_RELAX, m.full_window, _no_shot(), safety=0.9, alpha=alpha, rest_ke=-1.0, rest_v=0.0,
                  e_ref=0.0, max_steps=n, record_every=1, record_capacity=n, raise_on_error=False)
    assert res.status == S.ST_MAX_STEPS  # all n steps ran, nothing went wrong
    return res


def kinetic(m, st):
    return 0.5 * float(np.sum(m.mass[:, None] * st.v**2))


def test_a_free_body_in_uniform_motion_translates_rigidly():
    m = box(lateral="free", bottom="free")
    st = m.new_state()
    v0 = np.array([3.0, -2.0, 5.0])
    st.v[:] = v0
    t0 = float(st.ctl[S.C_TIME])
    steps(m, st, 30)
    t = float(st.ctl[S.C_TIME]) - t0
    assert t > 0
    np.testing.assert_allclose(st.x - m.nodes0, np.outer(np.ones(len(st.x)), v0 * t), rtol=0, atol=1e-12 * H)
    np.testing.assert_allclose(st.v, np.outer(np.ones(len(st.v)), v0), rtol=1e-12)
    assert np.abs(st.stress).max() <= 1e-6 * MAT.A * 1e-3 and not st.eps_p.any()


def test_the_stable_step_is_below_the_element_transit_time():
    """The step a wave needs to cross the smallest element (h / c_p) bounds the explicit step."""
    m = box()
    st = m.new_state()
    st.v[:, 2] = 1.0 * np.sin(np.pi * m.nodes0[:, 2] / (6 * H))
    t0 = float(st.ctl[S.C_TIME])
    steps(m, st, 20)
    dt = (float(st.ctl[S.C_TIME]) - t0) / 20
    assert 0.2 * H / MAT.wave_speed < dt <= 0.9 * H / MAT.wave_speed


def test_undamped_vibration_keeps_its_energy_and_damping_removes_it():
    """The lowest compression mode of the clamped column (period 4 L / c_p ~ 24 steps), 400 steps. Kinetic
    energy comes from half-step velocities, off by O(omega dt) in phase with the strain energy, so the
    balance is checked on its mean over the last 10 periods."""
    m = box()
    z = m.nodes0[:, 2]
    L = z.max()
    out = {}
    for name, alpha in (("undamped", 0.0), ("damped", m.settle_alpha(m.full_window, 1.0))):
        st = m.new_state()
        st.v[:, 2] = 2.0 * np.sin(0.5 * np.pi * (L - z) / L)
        e0 = kinetic(m, st)
        r = steps(m, st, 400, alpha).records
        ke, strain, visc, damp = r[:, 10], r[:, 12] + r[:, 14], r[:, 15], r[:, 17]
        out[name] = (e0, ke, strain, visc, damp, st)
    e0, ke, strain, visc, damp, st = out["undamped"]
    assert strain.max() > 0.5 * e0  # energy really moves into strain and back (the column vibrates)
    assert damp.max() == 0.0 and not st.eps_p.any()  # undamped and elastic: only bulk viscosity dissipates
    assert np.mean((ke + strain + visc)[-240:]) == pytest.approx(e0, rel=0.01)
    e0, ke, strain, visc, damp, _ = out["damped"]
    assert np.mean((ke + strain)[-24:]) < 0.05 * e0 and damp[-1] > visc[-1]  # damping took most of it
    assert np.mean((ke + strain + visc + damp)[-240:]) == pytest.approx(e0, rel=0.01)
