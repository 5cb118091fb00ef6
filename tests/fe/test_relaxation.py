"""Global relaxation: the static (multigrid) method against strict dynamic relaxation."""

import numpy as np
import pytest

from peenflow.fe import solver as S
from peenflow.fe.element import element_rows
from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import graded_box
from peenflow.fe.model import Model, Target
from peenflow.fe.boundary import mask_fixed
from peenflow.fe.box_stiffness import BOX_PATTERN, ElementMatrices, element_bound, element_matrix, modal_blocks
from peenflow.fe.box_stiffness_reference import apply_k, apply_k_modal
from peenflow.fe.multigrid import Multigrid, dot
from peenflow.fe.relaxation import relax
from peenflow.fe.shots import Shots
from peenflow.testing import SAE1070

R = 0.29e-3


def box(bottom="fixed"):
    return Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3, fine_depth=0.1e-3), bottom=bottom)


@pytest.fixture(scope="module")
def unrelaxed():
    """Two windowed impacts, not relaxed: the held window faces leave the mesh out of equilibrium."""
    t = box()
    mat = Material(**SAE1070)
    shots = Shots(centres=[[0, 0, -R - 1e-6], [60e-6, -40e-6, -R - 5e-6]], velocities=[[0, 0, 55.0], [5.0, 0, 40.0]],
                  radius=R, density=7800.0)
    res = run_impacts(t, mat, shots, Options(final_relaxation=False))
    return t, mat, res.final_state, 0.5 * shots.mass * 55.0**2


def _profile(model, st, half=0.15e-3):
    c = model.centroids
    sel = (np.abs(c[:, 0]) <= half) & (np.abs(c[:, 1]) <= half)
    return np.array([st.stress[sel & (c[:, 2] == z), 0].mean() for z in np.unique(c[:, 2])])


def test_static_matches_strict_relaxation(unrelaxed):
    """Static relaxation at the default tolerance against (a) itself at a
    very strict tolerance and (b) strict dynamic relaxation.

    Measured on this box: (a) profile 4e-5 of its peak, displacements 2e-6
    of the largest; (b) profile 1.8e-4, displacements 1.3e-4, largest
    stress difference 0.5 % of the largest stress -- dynamic relaxation
    overshoots and yields 13 elements a little more (eps_p + 1.7e-4) on its
    way to rest, the static correction yields none. Thresholds ~3x those.

    The cheaper defaults (loose inner solves, ``relax_cg_rtol = 0.3``, and a
    10x stricter imbalance criterion, STATIC_ENERGY_FACTOR = 1e-3) keep (a)
    within the same thresholds (measured: profile 1.7e-5, displacements
    1.5e-6, stresses 0.11 MPa; the old defaults 3.7e-5, 1.7e-6, 0.24 MPa)
    for 8 V-cycles instead of 16.
    """
    t, mat, st0, e_ref = unrelaxed
    m = Model(t, mat)
    stat, rs = relax(m, st0, Options(), e_ref, 55.0)
    assert rs.status == S.ST_OK and rs.info[S.I_STEPS] <= 8
    assert rs.records[:, 1].sum() + 1 <= 10  # V-cycles: one per energy check + CG's further ones
    strict, _ = relax(m, st0, Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4), e_ref, 55.0)
    dyn, _ = relax(m, st0, Options(relax_method="dynamic", relax_ke_fraction=1e-11, relax_v_fraction=1e-6), e_ref, 55.0)
    p, ps, pd = _profile(m, stat), _profile(m, strict), _profile(m, dyn)
    u, us, ud = stat.x - m.nodes0, strict.x - m.nodes0, dyn.x - m.nodes0
    assert np.abs(p - ps).max() < 2e-4 * np.abs(ps).max()
    assert np.abs(u - us).max() < 1e-5 * np.abs(us).max()
    assert np.abs(p - pd).max() < 6e-4 * np.abs(pd).max()
    assert np.abs(u - ud).max() < 4e-4 * np.abs(ud).max()
    assert np.abs(stat.stress - dyn.stress).max() < 0.015 * np.abs(dyn.stress).max()
    # the static correction does not touch the plastic state; v = 0 at rest
    assert np.array_equal(stat.eps_p, st0.eps_p)
    assert np.abs(dyn.eps_p - st0.eps_p).max() < 1e-3
    assert not stat.v.any()
    # the relaxation really moved the state (the window faces were out of equilibrium)
    assert np.abs(u - (st0.x - m.nodes0)).max() > 1e-3 * np.abs(u).max()


def test_the_loosest_study_tolerance_keeps_its_stated_error(unrelaxed):
    """``fidelity.relaxation_tolerance`` admits up to 1e-3 (peenflow.study.bounds), stated in
    docs/performance.md section 3 from the paper's 6D REV as: the averaged profile within 0.21 % of the
    strict solve's peak and every stress within 14 MPa. On this second REV (two windowed impacts,
    25 um) the loosest tolerance keeps both (measured: 0.12 %, 6.3 MPa, 3 element passes against
    8 at 1e-7), and it is a real loosening (the profile moves by more than at 1e-7: 0.0009 %)."""
    from peenflow.study.bounds import BOUNDS

    loosest = next(b.high for b in BOUNDS if b.key == "fidelity.relaxation_tolerance")
    assert loosest == 1e-3
    t, mat, st0, e_ref = unrelaxed
    m = Model(t, mat)
    strict, _ = relax(m, st0, Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4), e_ref, 55.0)
    loose, rs = relax(m, st0, Options(relax_ke_fraction=loosest), e_ref, 55.0)
    tight, rt = relax(m, st0, Options(relax_ke_fraction=1e-7), e_ref, 55.0)
    assert rs.status == S.ST_OK and rs.info[S.I_STEPS] < rt.info[S.I_STEPS]
    ps = _profile(m, strict)
    err = np.abs(_profile(m, loose) - ps).max() / np.abs(ps).max()
    assert err <= 0.0021
    assert np.abs(loose.stress - strict.stress).max() <= 14e6
    assert err > np.abs(_profile(m, tight) - ps).max() / np.abs(ps).max()


def test_static_relaxation_of_a_state_at_rest_is_a_no_op(unrelaxed):
    t, mat, st0, e_ref = unrelaxed
    m = Model(t, mat)
    once, _ = relax(m, st0, Options(relax_ke_fraction=1e-12), e_ref, 55.0)
    twice, rs = relax(m, once, Options(), e_ref, 55.0)
    assert rs.info[S.I_STEPS] == 1 and len(rs.records) == 0
    assert np.array_equal(once.x, twice.x) and np.array_equal(once.stress, twice.stress)


def test_multigrid_operator_is_the_element_tangent_and_preconditioner_spd():
    t = box()
    m = Model(t, Material(**SAE1070))
    mg = Multigrid(m.mesh, m.bc, m.mat_static)
    assert mg.n_levels >= 2
    rng = np.random.default_rng(3)
    n = len(m.nodes0)
    u = rng.standard_normal((n, 3)) * 1e-10
    mask_fixed(u, m.bc)
    ku = np.empty_like(u)
    mg.levels[0].apply(u, ku)
    # the solver's element pass at the reference geometry, displacement u over 1 s
    st = m.new_state()
    st.x[:] += u
    st.v[:] = u
    element_rows(st.x, st.v, st.f, st.stress, st.eps_p, np.full(m.mesh.n_elements, 1e300), st.hg, st.temp, m.vol0,
                 m.mat_static, 1.0, m.nnx, m.nny, m.nx, m.ny, 0, m.nx, 0, m.ny, 0, m.nz)
    f = -st.f
    mask_fixed(f, m.bc)
    assert np.abs(ku - f).max() < 1e-5 * np.abs(f).max()
    # V-cycle: symmetric positive definite
    a, b = rng.standard_normal((2, n, 3))
    mask_fixed(a, m.bc)
    mask_fixed(b, m.bc)
    ma, mb = mg.vcycle(a), mg.vcycle(b)
    assert dot(a, ma) > 0 and dot(b, mb) > 0
    assert dot(a, mb) == pytest.approx(dot(b, ma), rel=1e-9)


@pytest.mark.parametrize("hourglass_type", ["physical", "stiffness"])
def test_modal_apply_is_the_dense_element_matrix_apply(hourglass_type):
    """Every level applies its elements in modal form (the two blocks of a box element), the
    same operator as the dense 24 x 24 matrices to round-off; an element matrix that couples
    the blocks is told apart (the multigrid refuses it)."""
    m = Model(box(), Material(**SAE1070), hourglass_type=hourglass_type)
    mg = Multigrid(m.mesh, m.bc, m.mat_static)
    rng = np.random.default_rng(11)
    for lev in mg.levels:
        assert lev.modal is not None and len(lev.modal[0]) == len(BOX_PATTERN)  # the written-out product
        u = rng.standard_normal((lev.dinv.shape[0], 3))
        dense, box_, modal = np.empty_like(u), np.empty_like(u), np.empty_like(u)
        apply_k(u, dense, lev.ke, *lev.types, lev.nn[0], lev.nn[1], *lev.ne, lev.bc)
        lev.apply(u, box_)
        apply_k_modal(u, modal, *lev.modal, *lev.types, lev.nn[0], lev.nn[1], *lev.ne, lev.bc)  # index lists
        assert np.abs(box_ - dense).max() < 1e-13 * np.abs(dense).max()
        assert np.abs(modal - dense).max() < 1e-13 * np.abs(dense).max()
    ke = mg.levels[0].ke.reshape(-1, 24, 24)[:1].copy()
    ke[0, 0, 5] += 1e-6 * np.abs(ke).max()  # an x-y coupling of corners 0 and 1 outside the box's form
    ke[0, 5, 0] = ke[0, 0, 5]
    assert modal_blocks(ke)[3] > 1e-8


def test_free_bottom_falls_back_to_dynamic_relaxation():
    t = box(bottom="free")
    mat = Material(**SAE1070)
    shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 30.0]], radius=R, density=7800.0)
    a = run_impacts(t, mat, shots, Options())
    b = run_impacts(t, mat, shots, Options(relax_method="dynamic"))
    assert np.array_equal(a.stress, b.stress) and np.array_equal(a.displacement, b.displacement)


def test_element_matrices_span_every_box_size():
    """Six probed boxes give any box's matrix (to the probe's own accuracy);
    an element outside that form falls back to probing every size."""
    mat = Model(box(), Material(**SAE1070)).mat_static
    em = ElementMatrices(mat, 25e-6)
    assert em.spanned
    for h in ((25e-6, 25e-6, 25e-6), (25e-6, 40e-6, 170e-6), (300e-6, 12.5e-6, 6e-6)):
        k = element_matrix(*h, mat)
        assert np.abs(em(*h) - k).max() < 1e-9 * np.abs(k).max()
    # the span check is a real one: a tolerance below the probe's accuracy fails it
    import peenflow.fe.box_stiffness as BS
    saved, BS.SPAN_TOLERANCE = BS.SPAN_TOLERANCE, 1e-16
    try:
        em2 = ElementMatrices(mat, 25e-6)
    finally:
        BS.SPAN_TOLERANCE = saved
    assert not em2.spanned
    h = (25e-6, 40e-6, 170e-6)
    assert np.array_equal(em2(*h), 0.5 * (element_matrix(*h, mat) + element_matrix(*h, mat).T))


@pytest.mark.parametrize("hourglass_type", ["physical", "stiffness"])
def test_element_bound_is_an_upper_bound_of_the_smoother_spectrum(hourglass_type):
    m = Model(box(), Material(**SAE1070), hourglass_type=hourglass_type)
    lev = Multigrid(m.mesh, m.bc, m.mat_static).levels[0]
    bound = element_bound(lev.ke)
    rng = np.random.default_rng(5)
    u = rng.standard_normal((len(m.nodes0), 3)) * (lev.dinv != 0)
    ku = np.empty_like(u)
    lam = 0.0
    for _ in range(60):  # power iteration on D^-1 K
        u /= np.sqrt(dot(u, u))
        lev.apply(u, ku)
        z = lev.dinv * ku
        lam = np.sqrt(dot(z, z))
        u = z
    assert lam <= bound * (1 + 1e-12)
    if hourglass_type == "stiffness":
        assert bound < 1.2 * lam  # and a tight one on the fine level
    # The physical form's bending modes make the element-wise bound looser
    # (measured 1.32 x the power-iteration value); it stays an upper bound,
    # and what it costs is held by the V-cycle budget that
    # test_static_matches_strict_relaxation asserts (<= 10), not claimed here.
