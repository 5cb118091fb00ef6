"""One-point hexahedron: patch test, rigid-body motion, objectivity, hourglass."""

import numpy as np
import pytest

from peenflow.fe.element_reference import element_pass
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis

MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1e12)  # elastic


def _mesh():
    ax = graded_axis(2e-5, 1e-5, 6e-5, 1.2)  # non-uniform spacing
    return BoxMesh(ax, ax * 1.3, ax * 0.7)


def _arrays(mesh):
    n, ne = mesh.n_nodes, mesh.n_elements
    return dict(
        f=np.zeros((n, 3)), stress=np.zeros((ne, 6)), eps_p=np.zeros(ne), sy=np.full(ne, 1e12),
        hg=np.zeros((ne, 12)), temp=np.full(ne, 293.0), vol0=mesh.element_volumes(),
    )


def _pass(mesh, a, x, v, dt, mat=None):
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    a["f"][:] = 0.0
    return element_pass(x, v, a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"],
                        MAT.to_array() if mat is None else mat, dt, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)


def _interior(mesh):
    nnx, nny, nnz = mesh.shape_nodes
    idx = np.arange(mesh.n_nodes).reshape(nnz, nny, nnx)
    return idx[1:-1, 1:-1, 1:-1].ravel()


def test_patch_uniform_strain_exact():
    mesh = _mesh()
    a = _arrays(mesh)
    X = mesh.node_coordinates()
    G = np.array([[2e-4, 1e-4, -3e-5], [4e-5, -1e-4, 2e-5], [-6e-5, 7e-5, 3e-4]])
    dt = 1e-9
    x = X @ (np.eye(3) + G).T
    v = (X @ G.T) / dt
    dtn, status, *_ = _pass(mesh, a, x, v, dt)
    assert status == 0
    # exact rate: L = G (I + G/2)^-1 / dt at the mid-step configuration
    L = G @ np.linalg.inv(np.eye(3) + 0.5 * G) / dt
    D = 0.5 * (L + L.T)
    sig = MAT.lam * np.trace(D) * dt * np.eye(3) + 2 * MAT.mu * D * dt
    expected = np.array([sig[0, 0], sig[1, 1], sig[2, 2], sig[1, 2], sig[0, 2], sig[0, 1]])
    scale = np.abs(expected).max()
    np.testing.assert_allclose(a["stress"], np.broadcast_to(expected, a["stress"].shape), rtol=0, atol=1e-12 * scale)
    # interior nodes are in equilibrium (forces cancel to round-off of one element force)
    fscale = scale * 1e-10
    assert np.abs(a["f"][_interior(mesh)]).max() < 1e-10 * fscale
    # no hourglass response to a linear field
    assert np.abs(a["hg"]).max() < 1e-12 * fscale


def test_uniform_strain_on_distorted_mesh():
    mesh = _mesh()
    a = _arrays(mesh)
    rng = np.random.default_rng(1)
    X = mesh.node_coordinates() + rng.uniform(-2e-6, 2e-6, (mesh.n_nodes, 3))  # ~20% of h
    a["vol0"][:] = 1.0  # only used for the distortion check here
    G = np.array([[1e-4, 2e-5, 0.0], [0.0, -5e-5, 1e-5], [3e-5, 0.0, 2e-4]])
    dt = 1e-9
    _pass(mesh, a, X @ (np.eye(3) + G).T, (X @ G.T) / dt, dt, MAT.to_array())
    s = a["stress"]
    np.testing.assert_allclose(s, np.broadcast_to(s[0], s.shape), rtol=0, atol=1e-9 * np.abs(s[0]).max())


def _rotation(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_rigid_translation_and_rotation_create_no_stress():
    mesh = _mesh()
    a = _arrays(mesh)
    X = mesh.node_coordinates()
    dt = 1e-9
    n = 100
    for k in range(n):
        x0 = X @ _rotation(0.5 * np.pi * k / n).T + 1e-6 * k
        x1 = X @ _rotation(0.5 * np.pi * (k + 1) / n).T + 1e-6 * (k + 1)
        _, status, *_ = _pass(mesh, a, x1, (x1 - x0) / dt, dt)
        assert status == 0
    # a rigid rotation has D = 0 exactly at the mid-step configuration (Cayley);
    # what is left is round-off: ~1e-16 relative position noise per step is a
    # strain noise ~1e-15 (E x 1e-15 = 2e-4 Pa) per step; a real strain of
    # 1e-6 would give 2e5 Pa
    assert np.abs(a["stress"]).max() < 1e-2
    assert np.abs(a["hg"]).max() < 1e-9


def test_jaumann_rate_rotates_prestress():
    mesh = _mesh()
    a = _arrays(mesh)
    a["stress"][:, 0] = 1e8  # uniaxial sigma_xx
    X = mesh.node_coordinates()
    dt = 1e-9
    n = 1000
    for k in range(n):
        x0 = X @ _rotation(0.5 * np.pi * k / n).T
        x1 = X @ _rotation(0.5 * np.pi * (k + 1) / n).T
        _pass(mesh, a, x1, (x1 - x0) / dt, dt)
    s = a["stress"][0]
    # after 90 degrees about z the stress is sigma_yy; explicit Jaumann update
    # error ~ (pi/2)^2 / (2 n) = 1.2e-3 for n = 1000
    assert s[1] == pytest.approx(1e8, rel=3e-3)
    assert abs(s[0]) < 3e-3 * 1e8 and abs(s[5]) < 3e-3 * 1e8


def test_stable_step_of_a_cube():
    # cube of side h: omega^2 = 4 c^2 / h^2 + 32 Q_hg c^2 / h^2 -> dt = h / (c sqrt(1 + 8 Q_hg))
    h = 1e-5
    ax = np.array([0.0, h, 2 * h])
    mesh = BoxMesh(ax, ax, ax)
    a = _arrays(mesh)
    X = mesh.node_coordinates()
    dtn, status, *_ = _pass(mesh, a, X, np.zeros_like(X), 0.0)
    q = MAT.to_array()[17]
    assert dtn == pytest.approx(h / (MAT.wave_speed * np.sqrt(1 + 8 * q)), rel=1e-12)


def test_inverted_element_is_reported():
    mesh = _mesh()
    a = _arrays(mesh)
    X = mesh.node_coordinates().copy()
    X[:, 2] *= -1.0  # mirror: every element inside out
    _, status, *_ = _pass(mesh, a, X, np.zeros_like(X), 1e-9)
    assert status == 2


def test_blocked_pass_matches_reference_pass():
    from peenflow.fe.element import element_rows

    mesh = BoxMesh(*(np.arange(12) * 1e-5,) * 2, np.arange(7) * 1e-5)
    rng = np.random.default_rng(3)
    X = mesh.node_coordinates() + rng.normal(0, 5e-7, (mesh.n_nodes, 3))
    v = rng.normal(0, 2.0, X.shape)
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=1e8, B=6e8, n=0.234, C=0.0134).to_array()
    out = []
    for fn in (element_pass, element_rows):
        a = _arrays(mesh)
        a["sy"][:] = 1e8
        a["stress"][:] = rng.normal(0, 1e8, a["stress"].shape) if not out else out[0][1]["stress0"]
        s0 = a["stress"].copy()
        r = fn(X, v, a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"], mat, 2e-9,
               nnx, nny, nx, ny, 1, nx, 0, ny - 1, 0, nz)
        a["stress0"] = s0
        out.append((r, a))
    (r1, a1), (r2, a2) = out
    assert r1[1] == r2[1] == 0
    assert r1[0] == pytest.approx(r2[0], rel=1e-14)
    for k in ("f", "stress", "eps_p", "hg", "sy"):
        scale = np.abs(a1[k]).max()
        assert scale > 0
        np.testing.assert_allclose(a2[k], a1[k], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(r2[2:], r1[2:], rtol=1e-10)
