"""Periodic lateral faces: tying, translation invariance across the seam, energy, determinism, relaxation."""

import numpy as np
import pytest

from peenflow.fe import solver as S
from peenflow.fe.boundary import TIED
from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.window import ViscousSpringFaces
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis, graded_box
from peenflow.fe.model import Model, Target
from peenflow.fe.relaxation import _forces, _no_shot, relax
from peenflow.fe.shots import Shots
from peenflow.testing import SAE1070

R = 0.29e-3
H = 50e-6
MAT = Material(**SAE1070)


def block(n, lateral="periodic"):
    """n x n elements of 50 um laterally, 0.6 mm deep (graded below 0.2 mm)."""
    ax = np.linspace(-0.5 * n * H, 0.5 * n * H, n + 1)
    return Target(BoxMesh(ax, ax.copy(), graded_axis(0.2e-3, H, 0.6e-3, 1.2)), lateral=lateral)


def shots_at(xy, v=(0.0, 0.0, 55.0)):
    return Shots(centres=[[x, y, -R - 1e-6] for x, y in xy], velocities=[v] * len(xy), radius=R, density=7800.0)


def aligned(a, t, k):
    """Element field ``a`` (n_el, c) moved back by ``k`` elements in x and y."""
    nx, ny, nz = t.mesh.shape_elements
    return np.roll(a.reshape(nz, ny, nx, -1), (-k, -k), axis=(1, 2))


def test_non_uniform_lateral_spacing_is_refused():
    with pytest.raises(ValueError, match="x axis is not uniform"):
        Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3), lateral="periodic")
    ax = np.linspace(0, 1e-3, 11)
    with pytest.raises(ValueError, match="y axis is not uniform"):
        Target(BoxMesh(ax, ax ** 1.1, ax), lateral="periodic")
    with pytest.raises(ValueError, match="lateral must be"):
        Target(BoxMesh(ax, ax, ax), lateral="periodical")


def test_uniform_shear_stays_uniform_across_the_seam():
    """A laterally uniform shear flow (v_x ~ depth, bottom held) stays laterally
    uniform with tied faces: the folded forces on the seam equal the interior's.
    With free faces it does not (the check can fail)."""
    spread = {}
    for lateral in ("periodic", "free"):
        t = block(8, lateral)
        m = Model(t, MAT)
        st = m.new_state()
        z = m.nodes0[:, 2]
        st.v[:, 0] = 2.0 * (z[-1] - z) / z[-1]
        st.v[:, 1] = 0.5 * (z[-1] - z) / z[-1]
        # undamped "relaxation" that never comes to rest: 40 plain steps, no shot
        res = m.phase(st, S.MODE_RELAX, m.full_window, _no_shot(), safety=0.9, alpha=0.0, rest_ke=-1.0, rest_v=0.0,
                      e_ref=0.0, max_steps=40, raise_on_error=False)
        assert res.status == S.ST_MAX_STEPS  # ran all 40 steps
        nx, ny, nz = t.mesh.shape_elements
        s = st.stress.reshape(nz, ny, nx, 6)
        spread[lateral] = np.max(s.max(axis=(1, 2)) - s.min(axis=(1, 2))) / np.abs(s).max()
        if lateral == "periodic":
            sl = np.nonzero(m.bc & TIED)[0]
            d = st.x[sl] - st.x[m.masters[sl]]
            lx, ly = m.period
            exp = np.column_stack([np.where(m.bc[sl] & 8, lx, 0.0), np.where(m.bc[sl] & 16, ly, 0.0), np.zeros(len(sl))])
            assert np.abs(d - exp).max() <= 1e-15
            assert np.array_equal(st.v[sl], st.v[m.masters[sl]])
    assert spread["periodic"] < 1e-9
    assert spread["free"] > 1e-3


@pytest.fixture(scope="module")
def centre_and_seam():
    """The same shot on a 24 x 24 periodic block landing on an element centre
    near the middle (no roll) and 11 elements further in x and y, across the
    seam (rolled): window smaller than the period."""
    t = block(24)
    out = []
    for k in (0, 11):
        x = 0.5 * H + k * H
        out.append(run_impacts(t, MAT, shots_at([(x, x)]), Options(final_relaxation=False)))
    return t, out


def test_seam_shot_equals_centre_shot(centre_and_seam):
    t, (a, b) = centre_and_seam
    assert a.shots["win_i0"][0] > 0 and a.shots["win_i1"][0] < 24  # no roll
    assert b.shots["win_i1"][0] > 24  # the window crossed the seam
    st_a, st_b = a.final_state, b.final_state
    sa = st_a.stress.reshape(aligned(st_a.stress, t, 0).shape)
    assert np.abs(aligned(st_b.stress, t, 11) - sa).max() <= 1e-9 * np.abs(sa).max()
    assert np.array_equal(aligned(st_b.eps_p[:, None], t, 11) > 0, aligned(st_a.eps_p[:, None], t, 0) > 0)
    for key in ("restitution", "max_approach", "peak_force", "energy_error"):
        assert b.shots[key][0] == pytest.approx(a.shots[key][0], rel=1e-9)
    # energy balance closed (same bound as the symmetric tests' windowed plastic impact)
    assert a.energy_error < 0.02 and b.energy_error < 0.02


def test_window_spanning_the_period_ties_the_faces():
    """Window wider than the period (and no window): the solver's tying carries the
    waves across the seam; a shot one element from the seam matches a centred one."""
    t = block(19)
    for opts in (Options(window_lateral=6.0, final_relaxation=False), Options(window=False, final_relaxation=False)):
        a = run_impacts(t, MAT, shots_at([(0.0, 0.0)], (0, 0, 40.0)), opts)
        b = run_impacts(t, MAT, shots_at([(9 * H, 9 * H)], (0, 0, 40.0)), opts)
        assert (a.shots["win_i0"][0], a.shots["win_i1"][0]) == (0, 19)
        sa = aligned(a.final_state.stress, t, 0)
        assert np.abs(aligned(b.final_state.stress, t, 9) - sa).max() <= 1e-9 * np.abs(sa).max()
        assert a.energy_error < 0.02


def test_relaxation_leaves_no_imbalance_on_the_seam(centre_and_seam):
    t, (_, b) = centre_and_seam
    m = Model(t, MAT)
    e_ref = 0.5 * shots_at([(0, 0)]).mass * 55.0 ** 2
    st0 = b.final_state.copy()
    r0 = _forces(m, st0, 0.0, 1, "test")
    st, res = relax(m, b.final_state, Options(), e_ref, 55.0)
    assert res.status == S.ST_OK and len(res.records) > 0  # the static method converged (no fallback)
    r = _forces(m, st, 0.0, 1, "test")
    nn = t.mesh.shape_nodes
    r3 = np.abs(r).reshape(nn[2], nn[1], nn[0], 3)
    assert np.abs(r0).max() > 0
    # seam masters (i = 0 or j = 0) as balanced as anywhere, 1e-3 of the start
    assert max(r3[:, :, 0].max(), r3[:, 0, :].max()) <= 1e-3 * np.abs(r0).max()
    assert r3[:, :, -1].max() == 0.0 and r3[:, -1, :].max() == 0.0  # slaves carry nothing of their own
    # static against strict dynamic relaxation with tying
    ref, _ = relax(m, b.final_state, Options(relax_method="dynamic", relax_ke_fraction=1e-10, relax_v_fraction=1e-5),
                   e_ref, 55.0)
    assert np.abs(st.stress - ref.stress).max() <= 0.02 * np.abs(ref.stress).max()
    # and the relaxed seam shot still matches the relaxed centred one, to the relaxation's tolerance
    a_rel, _ = relax(m, centre_and_seam[1][0].final_state, Options(), e_ref, 55.0)
    sa = aligned(a_rel.stress, t, 0)
    assert np.abs(aligned(st.stress, t, 11) - sa).max() <= 1e-3 * np.abs(sa).max()


def test_no_symmetric_mass_fraction_on_a_periodic_face():
    t = block(24)
    x0 = t.mesh.x[0]
    res = run_impacts(t, MAT, shots_at([(x0, 0.5 * H)]), Options(final_relaxation=False, record=True, record_every=50))
    assert res.histories[0]["mass_fraction"] == 1.0
    # the recorded centre is in the target's frame (the state was rolled for the impact)
    assert abs(res.histories[0]["centre"][0, 0] - x0) < 2 * H


def test_periodic_threads_and_resume_bit_identical(monkeypatch):
    from peenflow.fe import model

    monkeypatch.setattr(model, "PARALLEL_MIN_ELEMENTS", 0)
    t = block(24)
    L = 24 * H
    sh = Shots(centres=[[0.5 * L - H, 0.5 * L, -R - 1e-6], [0.0, 0.0, -R - 1e-6], [-0.5 * L + 0.3 * H, 0.1e-3, -R - 1e-6]],
               velocities=[[0, 0, 40.0], [5.0, 0, 40.0], [0, -4.0, 40.0]], radius=R, density=7800.0)
    saved = {}

    def cb(i, exporter):
        if i == 0:
            saved["state"] = exporter()

    a = run_impacts(t, MAT, sh, Options(), on_shot_done=cb)
    c = run_impacts(t, MAT, sh, Options(), state=saved["state"])
    assert np.array_equal(a.stress, c.stress) and np.array_equal(a.displacement, c.displacement)
    assert np.array_equal(a.eps_p, c.eps_p)
    for k in a.shots:
        np.testing.assert_array_equal(a.shots[k], c.shots[k])
    # 2 threads: a tied full-mesh phase and a static relaxation (below); a whole
    # seam-shot run in test_periodic_two_threads_whole_run (slow: on a loaded
    # machine the parallel pass's per-step join costs ~10 ms)
    m = Model(t, MAT)
    e_ref = 0.5 * sh.mass * 40.0 ** 2
    out = []
    for threads in (1, 2):
        st = a.final_state.copy()
        st.v[:, 0] = 0.3 * np.sin(m.nodes0[:, 0] * 2 * np.pi / L)  # crosses the seam
        m.unfold(st.v)
        m.phase(st, S.MODE_RELAX, m.full_window, _no_shot(), safety=0.9, alpha=0.0, rest_ke=-1.0, rest_v=0.0,
                e_ref=0.0, max_steps=30, threads=threads, raise_on_error=False)
        rs, res = relax(m, st, Options(threads=threads), e_ref, 40.0)
        assert res.status == S.ST_OK
        out.append(rs)
    assert np.array_equal(out[0].x, out[1].x) and np.array_equal(out[0].stress, out[1].stress)


@pytest.mark.slow
def test_periodic_two_threads_whole_run(monkeypatch):
    from peenflow.fe import model

    monkeypatch.setattr(model, "PARALLEL_MIN_ELEMENTS", 0)
    t = block(24)
    one = shots_at([(12 * H - H, 12 * H)], (0, 0, 40.0))
    a = run_impacts(t, MAT, one, Options())
    b = run_impacts(t, MAT, one, Options(threads=2))
    assert np.array_equal(a.stress, b.stress) and np.array_equal(a.displacement, b.displacement)


def test_contact_wider_than_half_the_period_is_refused():
    with pytest.raises(ValueError, match="too short for the shot's contact"):
        run_impacts(block(12), MAT, shots_at([(0.0, 0.0)]), Options())


def test_window_touching_the_seam_must_span_it():
    t = block(12)
    m = Model(t, MAT)
    st = m.new_state()
    with pytest.raises(ValueError, match="must span the period along x"):
        m.phase(st, S.MODE_RELAX, np.array([0, 5, 2, 8, 0, 3]), _no_shot(), safety=0.9, alpha=1.0, rest_ke=1.0,
                rest_v=1.0, e_ref=0.0)


def test_task_targets():
    """REV tasks take fidelity.lateral_boundary; impact blocks (quarter/half models) stay symmetric."""
    from tasks import _kernel as K
    from tasks.params import FidelityParams

    f = FidelityParams(element_size_m=H, fine_depth_m=0.2e-3, grading_ratio=1.2, time_step_safety=0.5,
                       window_contact_radii=4.0, settle_tolerance=1e-6, relaxation_tolerance=1e-8,
                       lateral_boundary="periodic")
    rev = K.rev_mesh(f, 24 * H, 0.6e-3)
    assert f.boundary(rev).lateral == "periodic"
    blk = K.impact_block(f, 0.6e-3, 0.6e-3, 0.2e-3, symmetric_x=True, symmetric_y=True)
    assert f.boundary(blk, impact_block=True).lateral == "symmetric"


def test_shot_beyond_the_mesh_wraps():
    t = block(24)
    L = 24 * H
    x = 0.5 * L + 2.5 * H  # lands 2.5 elements past the x+ face: the same as 2.5 past the x- face
    a = run_impacts(t, MAT, shots_at([(x, 0.5 * H)]), Options(final_relaxation=False))
    b = run_impacts(t, MAT, shots_at([(x - L, 0.5 * H)]), Options(final_relaxation=False))
    assert a.shots["hit"][0] == 1.0
    sa = a.final_state.stress
    assert np.abs(b.final_state.stress - sa).max() <= 1e-9 * np.abs(sa).max()


@pytest.mark.parametrize("opts", [Options(window_faces=ViscousSpringFaces(), final_relaxation=False),
                                  Options(window_sponge=0.2, final_relaxation=False)])
def test_seam_shot_other_window_faces(opts):
    """Viscous-spring and sponge window faces: the seam shot matches the centred one too."""
    t = block(24)
    a = run_impacts(t, MAT, shots_at([(0.5 * H, 0.5 * H)]), opts)
    b = run_impacts(t, MAT, shots_at([(11.5 * H, 11.5 * H)]), opts)
    sa = aligned(a.final_state.stress, t, 0)
    assert np.abs(aligned(b.final_state.stress, t, 11) - sa).max() <= 1e-9 * np.abs(sa).max()


def test_periodic_multigrid_is_the_tied_tangent_and_spd():
    """Level 0 applies T^T K T (the folded element forces of an unfolded
    displacement); the V-cycle is symmetric positive definite on the tied space."""
    from peenflow.fe.element import element_rows
    from peenflow.fe.boundary import mask_fixed
    from peenflow.fe.multigrid import Multigrid, dot

    m = Model(block(16), MAT)
    mg = Multigrid(m.mesh, m.bc, m.mat_static, periodic=True)
    assert mg.n_levels >= 2
    rng = np.random.default_rng(5)
    n = len(m.nodes0)

    def tied(a):
        mask_fixed(a, m.bc)
        a[m.bc & TIED != 0] = 0.0  # master-only vectors
        return a

    u = tied(rng.standard_normal((n, 3)) * 1e-10)
    ku = np.empty_like(u)
    mg.levels[0].apply(u, ku)
    st = m.new_state()
    uu = m.unfold(u.copy())
    st.x[:] += uu
    st.v[:] = uu
    element_rows(st.x, st.v, st.f, st.stress, st.eps_p, np.full(m.mesh.n_elements, 1e300), st.hg, st.temp, m.vol0,
                 m.mat_static, 1.0, m.nnx, m.nny, m.nx, m.ny, 0, m.nx, 0, m.ny, 0, m.nz)
    f = m.fold(-st.f)
    mask_fixed(f, m.bc)
    assert np.abs(ku - f).max() < 1e-5 * np.abs(f).max()
    a, b = tied(rng.standard_normal((n, 3))), tied(rng.standard_normal((n, 3)))
    ma, mb = mg.vcycle(a), mg.vcycle(b)
    assert not np.any(ma[m.bc & TIED != 0])
    assert dot(a, ma) > 0 and dot(b, mb) > 0
    assert dot(a, mb) == pytest.approx(dot(b, ma), rel=1e-9)


def test_periodic_free_bottom_relaxes_dynamically():
    """Free bottom: no static method (rigid lateral drift); dynamic relaxation with
    tying, and the seam shot still matches the centred one."""
    t = Target(block(24).mesh, lateral="periodic", bottom="free")
    a = run_impacts(t, MAT, shots_at([(0.5 * H, 0.5 * H)]), Options())
    b = run_impacts(t, MAT, shots_at([(11.5 * H, 11.5 * H)]), Options())
    sa = aligned(a.stress, t, 0)
    assert np.abs(aligned(b.stress, t, 11) - sa).max() <= 1e-6 * np.abs(sa).max()
