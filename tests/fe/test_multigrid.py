"""The multigrid preconditioner (peenflow.fe.multigrid): CG with it solves the linear elastic problem of
the target to its tolerance, against a direct solve and against the exact uniaxial-strain answer, and one
V-cycle alone already removes most of the error."""

import numpy as np
import pytest

from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.model import Model, Target
from peenflow.fe.multigrid import dot, pcg

MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
H = 50e-6


@pytest.fixture(scope="module")
def system():
    """An 8 x 8 x 8 box of 50 um elements (729 nodes: two levels), symmetric sides, fixed bottom; its
    stiffness as a dense matrix on the free dofs."""
    ax = np.linspace(0.0, 8 * H, 9)
    m = Model(Target(BoxMesh(ax, ax.copy(), ax.copy())), MAT)
    mg = m.multigrid()
    lev = mg.levels[0]
    n = lev.dinv.shape[0]
    K = np.zeros((3 * n, 3 * n))
    e, out = np.zeros((n, 3)), np.empty((n, 3))
    for d in range(3 * n):
        e.flat[d] = 1.0
        lev.apply(e, out)
        K[:, d] = out.ravel()
        e.flat[d] = 0.0
    free = lev.dinv.ravel() != 0.0
    return m, mg, K, free


def test_two_levels_and_a_symmetric_positive_definite_operator(system):
    _, mg, K, free = system
    assert mg.n_levels >= 2
    Kf = K[np.ix_(free, free)]
    assert np.abs(Kf - Kf.T).max() <= 1e-9 * np.abs(Kf).max()
    assert np.linalg.eigvalsh(0.5 * (Kf + Kf.T)).min() > 0.0


def test_cg_reaches_its_tolerance_and_the_direct_solution(system):
    m, mg, K, free = system
    rng = np.random.default_rng(5)
    b = rng.standard_normal((len(free) // 3, 3)) * free.reshape(-1, 3)
    u, its, rel = pcg(mg, b, rtol=1e-10, max_iter=200)
    assert rel <= 1e-10 and its < 60
    direct = np.zeros(len(free))
    direct[free] = np.linalg.solve(K[np.ix_(free, free)], b.ravel()[free])
    assert np.abs(u.ravel() - direct).max() <= 1e-8 * np.abs(direct).max()
    # one V-cycle alone: the energy norm of the error falls to well under half
    err0 = direct.reshape(-1, 3)
    err1 = err0 - mg.vcycle(b)
    k = np.empty_like(err0)
    mg.levels[0].apply(err1, k)
    e1 = dot(err1, k)
    mg.levels[0].apply(err0, k)
    assert e1 < 0.25 * dot(err0, k)


def test_uniform_pressure_gives_the_uniaxial_strain_answer(system):
    """Pressure p on the top of a box with symmetric sides and a fixed bottom: uniaxial strain, the top
    sinks p L / (lambda + 2 mu), exactly for these elements (a uniform strain has no hourglass part)."""
    m, mg, _, _ = system
    p = 100e6
    nnx, nny, _ = m.mesh.shape_nodes
    tx = np.full(nnx, H)
    tx[[0, -1]] = 0.5 * H  # tributary lengths of the top nodes
    b = np.zeros((m.mesh.n_nodes, 3))
    b[: nnx * nny, 2] = p * np.outer(tx, tx).ravel()  # +z: into the target
    u, _, rel = pcg(mg, b, rtol=1e-12, max_iter=200)
    lam_2mu = MAT.E * (1 - MAT.nu) / ((1 + MAT.nu) * (1 - 2 * MAT.nu))
    depth = m.nodes0[:, 2]
    L = depth.max()
    np.testing.assert_allclose(u[:, 2], p * (L - depth) / lam_2mu, rtol=0, atol=1e-9 * p * L / lam_2mu)
    assert np.abs(u[:, :2]).max() <= 1e-9 * p * L / lam_2mu
