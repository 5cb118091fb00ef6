"""Physical (assumed-strain) hourglass stabilisation of the one-point hexahedron.

What makes it physical: pure bending of a rectangular element is exact (one
element through the thickness gives the Euler-Bernoulli deflection), a
linear field creates no hourglass force, a rigid rotation carries the stored
hourglass forces along (co-rotational), the stable step bounds the element's
highest frequency, and the vectorised rows agree with the reference element.
"""

import numpy as np
import pytest

from peenflow.fe.element import element_rows
from peenflow.fe.element_reference import element_pass
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.box_stiffness import _LOCAL, element_matrix

STEEL = Material(E=200e9, nu=0.3, density=7800.0, A=1e13)  # elastic


def _phys(material=STEEL, **kw):
    return material.to_array(0.0, 0.0, hourglass_type="physical", **kw)


def _stiff(material=STEEL):
    return material.to_array(0.0, 0.0, 0.05, 0.1, "stiffness")


def _arrays(mesh, sy=1e13):
    n, ne = mesh.n_nodes, mesh.n_elements
    return dict(f=np.zeros((n, 3)), stress=np.zeros((ne, 6)), eps_p=np.zeros(ne), sy=np.full(ne, sy),
                hg=np.zeros((ne, 12)), temp=np.full(ne, 293.0), vol0=mesh.element_volumes())


def _pass(mesh, a, x, v, dt, mat, fn=element_pass):
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    a["f"][:] = 0.0
    return fn(x, v, a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"], mat, dt,
              nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)


# ---------------------------------------------------------------- beam bending

def _beam_deflection(nx, nz, L, h, mat, load):
    """Static tip deflection of a square-section cantilever (nx x 1 x nz box elements) from the
    probed element matrix: x = 0 face held in x and z (exact for pure bending of a square
    section, whose anticlastic u_z vanishes at its corners), one node held in y. ``load``:
    "moment" (end couple 1 N m as the consistent forces of sigma = M z / I) or "shear" (1 N,
    uniform traction)."""
    hx, hy, hz = L / nx, h, h / nz
    Ke = element_matrix(hx, hy, hz, mat)
    nnx, nny, nnz = nx + 1, 2, nz + 1
    n = nnx * nny * nnz
    K = np.zeros((3 * n, 3 * n))
    for k in range(nz):
        for i in range(nx):
            dofs = np.array([3 * ((i + a) + nnx * (b + nny * (k + c))) + d for (a, b, c) in _LOCAL for d in range(3)])
            K[np.ix_(dofs, dofs)] += Ke
    f = np.zeros(3 * n)
    z = np.arange(nnz) * hz - h / 2
    inertia = h**4 / 12
    for j in range(nny):
        for k in range(nnz):
            node = nx + nnx * (j + nny * k)
            if load == "moment":  # integral of the hat function times M z / I over the node's segments
                fz = sum(hz * (2 * z[k] + z[o]) / 6 for o in (k - 1, k + 1) if 0 <= o < nnz) / inertia
                f[3 * node] = fz * h / 2
            else:
                f[3 * node + 2] = (0.5 if k in (0, nz) else 1.0) * hz * (h / 2) / h**2
    held = [3 * (nnx * (j + nny * k)) + d for j in range(nny) for k in range(nnz) for d in (0, 2)] + [1]
    free = np.setdiff1d(np.arange(3 * n), held)
    u = np.zeros(3 * n)
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    return np.mean([u[3 * (nx + nnx * (j + nny * k)) + 2] for j in range(nny) for k in range(nnz)])


@pytest.mark.parametrize("nx", [4, 10])
def test_pure_bending_one_element_thick_is_exact(nx):
    # end couple M on L = 10 h: Euler-Bernoulli (and exact elasticity) tip deflection -M L^2 / (2 E I);
    # the elements are 2.5:1 and 1:1 -- the assumed-strain modes make pure bending exact for any aspect
    L, h = 10e-3, 1e-3
    exact = -1.0 * L**2 / (2 * STEEL.E * h**4 / 12)
    assert _beam_deflection(nx, 1, L, h, _phys(), "moment") == pytest.approx(exact, rel=1e-6)
    # the tuned stiffness form (Q = 0.05) is 1.6-7x too stiff here: what a coefficient cannot get right
    assert _beam_deflection(nx, 1, L, h, _stiff(), "moment") / exact < 0.65


@pytest.mark.parametrize("nx, nz", [(5, 1), (10, 1), (10, 2)])
def test_cantilever_tip_load_matches_timoshenko(nx, nz):
    # tip force P: P L^3 / (3 E I) + P L / (kappa G A), kappa = 5/6 (L / h = 10: shear adds 0.8 %)
    L, h = 10e-3, 1e-3
    G = STEEL.E / (2 * (1 + STEEL.nu))
    exact = L**3 / (3 * STEEL.E * h**4 / 12) + L / (5 / 6 * G * h * h)
    assert _beam_deflection(nx, nz, L, h, _phys(), "shear") == pytest.approx(exact, rel=0.02)


# --------------------------------------------------------- kinematic invariants

def _mesh():
    ax = graded_axis(2e-5, 1e-5, 6e-5, 1.2)
    return BoxMesh(ax, ax * 1.3, ax * 0.7)


def test_patch_uniform_strain_exact_and_no_hourglass_force():
    G = np.array([[2e-4, 1e-4, -3e-5], [4e-5, -1e-4, 2e-5], [-6e-5, 7e-5, 3e-4]])
    dt = 1e-9
    rng = np.random.default_rng(1)
    for distortion in (0.0, 2e-6):  # box elements, then nodes moved by up to ~20 % of h
        mesh = _mesh()
        a = _arrays(mesh)
        X = mesh.node_coordinates() + rng.uniform(-distortion, distortion, (mesh.n_nodes, 3))
        _, status, _, _, w_hg, _ = _pass(mesh, a, X @ (np.eye(3) + G).T, (X @ G.T) / dt, dt, _phys())
        assert status == 0
        s = a["stress"]
        np.testing.assert_allclose(s, np.broadcast_to(s[0], s.shape), rtol=0, atol=1e-9 * np.abs(s[0]).max())
        force_scale = np.abs(s[0]).max() * 1e-10  # stress x face area (h ~ 1e-5 m), N
        # a linear velocity field has no hourglass rate on any hexahedron: no force, no energy
        assert np.abs(a["hg"]).max() < 1e-12 * force_scale
        assert abs(w_hg) < 1e-12 * force_scale * 1e-9
        if distortion == 0.0:  # interior nodes in equilibrium to round-off
            inner = np.arange(mesh.n_nodes).reshape(mesh.shape_nodes[::-1])[1:-1, 1:-1, 1:-1].ravel()
            assert np.abs(a["f"][inner]).max() < 1e-10 * force_scale


def _cayley(axis, angle):
    w = np.cross(np.eye(3), axis * angle)  # skew matrix of the increment
    return np.linalg.solve(np.eye(3) - 0.5 * w, np.eye(3) + 0.5 * w)


def test_rigid_rotation_carries_the_hourglass_forces_along():
    """An element with stored hourglass forces turned rigidly by 90 deg: the physical form's nodal
    forces turn with it and no hourglass work is done; the stiffness form keeps its forces global."""
    mesh = BoxMesh(np.array([0, 2e-5]), np.array([0, 1.5e-5]), np.array([0, 1e-5]))
    X = mesh.node_coordinates()
    d = X - X.mean(axis=0)
    mode = np.sign(d[:, 0] * d[:, 1])  # xi eta pattern: pure hourglass, no strain at the centre
    dt = 1e-9
    for mat, co_rotational in ((_phys(), True), (_stiff(), False)):
        a = _arrays(mesh)
        v = np.outer(mode, [0.3, 0.2, -0.1]) * 1e-2  # hourglass velocity over one step
        x = X + v * dt
        _pass(mesh, a, x, v, dt, mat)
        f0 = a["f"].copy()
        assert np.abs(a["hg"]).max() > 0 and np.abs(a["stress"]).max() < 1e-6
        axis = np.array([1.0, 2.0, 2.0]) / 3.0
        n = 200
        Rk = _cayley(axis, 0.5 * np.pi / n)
        w_total = 0.0
        c = x.mean(axis=0)
        for _ in range(n):
            x1 = c + (x - c) @ Rk.T
            _, status, _, _, w_hg, _ = _pass(mesh, a, x1, (x1 - x) / dt, dt, mat)
            assert status == 0
            w_total += w_hg
            x = x1
        Rt = np.linalg.matrix_power(Rk, n)
        _pass(mesh, a, x, np.zeros_like(x), dt, mat)
        rotated = f0 @ Rt.T
        err = np.abs(a["f"] - rotated).max() / np.abs(f0).max()
        if co_rotational:  # to the geometric change of the hourglass vectors between mid-step shapes (~1e-7)
            assert err < 1e-5
            assert abs(w_total) < 1e-9 * np.abs(f0).max() * 1e-5
        else:
            assert err > 0.1


def test_rigid_rotation_creates_no_hourglass_force():
    mesh = _mesh()
    a = _arrays(mesh)
    X = mesh.node_coordinates()
    dt = 1e-9
    x = X.copy()
    Rk = _cayley(np.array([0.0, 0.6, 0.8]), 0.5 * np.pi / 100)
    for _ in range(100):
        x1 = x @ Rk.T + 1e-8
        _, status, *_ = _pass(mesh, a, x1, (x1 - x) / dt, dt, _phys())
        assert status == 0
        x = x1
    # round-off only: a real hourglass strain of 1e-9 would store ~1e-6 N
    assert np.abs(a["hg"]).max() < 1e-12


# ------------------------------------------------------------------ stable step

def _omega_dt(box, mat, density):
    """Highest frequency of one free box element (probed stiffness, lumped mass) and the element's step."""
    K = element_matrix(*box, mat)
    omega = np.sqrt(np.linalg.eigvalsh(K).max() / (density * np.prod(box) / 8))
    mesh = BoxMesh(*(np.array([0.0, s]) for s in box))
    dt, status, *_ = _pass(mesh, _arrays(mesh), mesh.node_coordinates(), np.zeros((8, 3)), 0.0, mat)
    assert status == 0
    return omega, dt


@pytest.mark.parametrize("box", [(1e-5, 1e-5, 1e-5), (1e-5, 1e-5, 3e-6), (2e-5, 1e-5, 4e-6)])
@pytest.mark.parametrize("material", [STEEL, Material(E=71e9, nu=0.33, density=2780.0, A=1e13),
                                      Material(E=1e9, nu=0.49, density=1000.0, A=1e13)])
def test_stable_step_covers_the_hourglass_modes(box, material):
    # the physical modes stay below the element's uniform-strain (volumetric) mode, so they
    # never set the highest frequency; the step keeps the margin the stiffness form at its
    # default Q = 0.05 has always run with (its omega dt, which the stability sweep measured)
    om_phys, dt_phys = _omega_dt(box, _phys(material), material.density)
    om_bare, _ = _omega_dt(box, material.to_array(0.0, 0.0, 0.0, 1.0, "stiffness"), material.density)
    om_fb, dt_fb = _omega_dt(box, material.to_array(0.0, 0.0, 0.05, 1.0, "stiffness"), material.density)
    assert om_phys <= om_bare * (1 + 1e-9)
    assert om_phys * dt_phys <= om_fb * dt_fb * (1 + 1e-9)


# ---------------------------------------------------- reference vs production

@pytest.mark.parametrize("material", [
    Material(E=205e9, nu=0.29, density=7800.0, A=1e8, B=6e8, n=0.234, C=0.0134),
    Material(E=71e9, nu=0.33, density=2780.0, A=434e6, B=303.58e6, n=0.39)])
def test_rows_match_reference_element_physical(material):
    mesh = BoxMesh(*(np.arange(12) * 1e-5,) * 2, np.arange(7) * 1e-5)
    rng = np.random.default_rng(3)
    X = mesh.node_coordinates() + rng.normal(0, 5e-7, (mesh.n_nodes, 3))
    v = rng.normal(0, 2.0, X.shape)
    mat = material.to_array(hourglass_type="physical")
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    stress0 = rng.normal(0, 1e8, (mesh.n_elements, 6))
    hg0 = rng.normal(0, 1e-3, (mesh.n_elements, 12))  # stored forces (element frame)
    out = []
    for fn in (element_pass, element_rows):
        a = _arrays(mesh, sy=1e8)
        a["stress"][:] = stress0
        a["hg"][:] = hg0
        r = fn(X, v, a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"], mat, 2e-9,
               nnx, nny, nx, ny, 1, nx, 0, ny - 1, 0, nz)
        out.append((r, a))
    (r1, a1), (r2, a2) = out
    assert r1[1] == r2[1] == 0
    assert r1[0] == pytest.approx(r2[0], rel=1e-14)
    assert a1["eps_p"].max() > 0  # some elements yielded: the tangent path is exercised
    for k in ("f", "stress", "eps_p", "hg", "sy"):
        scale = np.abs(a1[k]).max()
        assert scale > 0
        np.testing.assert_allclose(a2[k], a1[k], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(r2[2:], r1[2:], rtol=1e-10)


def test_unknown_hourglass_type_is_refused():
    with pytest.raises(ValueError, match="hourglass_type = 'viscous'"):
        STEEL.to_array(hourglass_type="viscous")
