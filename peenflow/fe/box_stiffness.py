"""The stiffness K of the solver's element on a box grid, and the product K u.

What the multigrid (:mod:`peenflow.fe.multigrid`) is built from, on each of
its levels: a tensor grid of axis-aligned box elements (``BoxMesh``), nodes
numbered ``i + nnx (j + nny k)``, three displacement dofs per node (m), forces
in N. ``tx, ty, tz`` give each interval's index into the level's distinct
spacings, ``ke[tx[i], ty[j], tz[k]]`` (24 x 24, N/m) the matrix of the element
at ``(i, j, k)``; ``bc`` the per-node fixity bits (:mod:`peenflow.fe.boundary`),
whose dofs every product leaves zero.

The element. Each matrix is that of the solver's own element (one-point
hexahedron + Flanagan-Belytschko stiffness hourglass control, same
``mat`` vector), its 24 x 24 matrix *probed* from
:func:`peenflow.fe.element.element_rows` on a single box element (unit
displacement of each of the 24 dofs, tiny amplitude, huge step so bulk
viscosity vanishes), so the finest level is exactly the tangent of the
solver's element at the reference geometry, whatever the element's internal
conventions. A tensor grid has few distinct element sizes (``hx``, ``hy``,
``hz`` per axis), so one matrix per distinct (hx, hy, hz) is stored; they
are combined from six probed boxes (:class:`ElementMatrices`, checked
against direct probes). The operator applies each element in modal form
(Walsh-Hadamard transform of its corners, then the 21 + 24 nonzero entries
of the box element's uniform-strain and hourglass blocks, written out in
:func:`apply_k_box`): the same operator as the dense 24 x 24 product to
round-off, 4x faster (docs/performance.md section 3, "Multigrid setup"). The
dense product and the modal product with index lists, which the tests compare
it against, are in :mod:`peenflow.fe.box_stiffness_reference`.

The operators are serial and in a fixed order: results do not depend on the
numba thread count.
"""

from __future__ import annotations

import numpy as np

from peenflow._jit import jit
from peenflow.fe.boundary import mask_fixed
from peenflow.fe.element import element_rows

# local node order of the solver's element (offsets from the first node)
_LOCAL = ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))


def element_matrix(hx: float, hy: float, hz: float, mat: np.ndarray) -> np.ndarray:
    """24 x 24 stiffness (N/m) of the solver's element for an ``hx x hy x hz`` box.

    Dof order: local node I (solver order) x 3 components. Probed with the
    element pass: each column is ``-f / a`` for a displacement ``a`` of one
    dof applied over a step of 1 s (bulk viscosity ~ rate -> negligible),
    central difference over +-a; elastic (huge flow stress). Symmetrised.
    """
    X = np.array([[i * hx, j * hy, k * hz] for k in (0, 1) for j in (0, 1) for i in (0, 1)], dtype=np.float64)
    glob = [i + 2 * (j + 2 * k) for (i, j, k) in _LOCAL]
    a = 1e-6 * min(hx, hy, hz)
    K = np.zeros((24, 24))
    for d in range(24):
        node, comp = glob[d // 3], d % 3
        for sign in (1.0, -1.0):  # central difference: error ~ (a / h)^2
            x = X.copy()
            v = np.zeros((8, 3))
            x[node, comp] += sign * a
            v[node, comp] = sign * a  # over dt = 1 s
            f = np.zeros((8, 3))
            element_rows(x, v, f, np.zeros((1, 6)), np.zeros(1), np.full(1, 1e300), np.zeros((1, 12)),
                         np.full(1, 293.0), np.full(1, hx * hy * hz), mat, 1.0, 2, 2, 1, 1, 0, 1, 0, 1, 0, 1)
            K[:, d] -= sign * f[glob].ravel() / (2.0 * a)
    return 0.5 * (K + K.T)


#: boxes (in units of the mesh's median spacing) whose probed matrices span every box's (:class:`ElementMatrices`)
_BASIS_BOXES = ((1.0, 1.0, 1.0), (2.0, 1.0, 1.0), (1.0, 2.0, 1.0), (1.0, 1.0, 2.0), (2.0, 2.0, 1.0), (2.0, 1.0, 3.0))
#: boxes on which that span is checked against a direct probe
_CHECK_BOXES = ((1.0, 3.0, 0.5), (2.5, 1.2, 7.0))
#: largest relative difference (max abs / max abs) accepted in that check; the probe itself is good to ~1e-11
SPAN_TOLERANCE = 1e-8


def _scale_factors(hx: float, hy: float, hz: float) -> np.ndarray:
    """``V / (h_k h_l)`` for (k, l) = xx, yy, zz, xy, xz, yz (``V = hx hy hz``)."""
    h = (hx, hy, hz)
    v = hx * hy * hz
    return np.array([v / (h[k] * h[l]) for k, l in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))])


class ElementMatrices:
    """:func:`element_matrix` for many box sizes at the cost of a few probes.

    For a box, every gradient of the one-point hexahedron scales as ``1/h``
    along its axis, so its stiffness is ``sum_kl V / (h_k h_l) A_kl`` over
    the six axis pairs; the Flanagan-Belytschko hourglass stiffness
    (``~ V sum_k 1 / h_k^2``) adds to the three diagonal pairs. The six
    ``A_kl`` are solved for from six probed boxes, and the span is checked
    against a direct probe of two more boxes: an element whose stiffness is
    not of that form (another hourglass control) fails the check and every
    size is then probed directly, as before. A graded 104 k-element block
    needed 7 743 probed matrices (4.7 of its 5.9 s of multigrid setup).
    Results are kept per size.
    """

    def __init__(self, mat: np.ndarray, h_ref: float):
        self.mat = mat
        self._cache: dict = {}
        boxes = [tuple(h_ref * c for c in b) for b in _BASIS_BOXES]
        a = np.array([_scale_factors(*b) for b in boxes])
        probed = np.array([element_matrix(*b, mat) for b in boxes])
        self.basis = np.linalg.solve(a, probed.reshape(len(boxes), -1))
        self.spanned = True
        for b in _CHECK_BOXES:
            box = tuple(h_ref * c for c in b)
            k = element_matrix(*box, mat)
            if np.abs(self._span(*box) - k).max() > SPAN_TOLERANCE * np.abs(k).max():
                self.spanned = False
                break

    def _span(self, hx, hy, hz) -> np.ndarray:
        return (_scale_factors(hx, hy, hz) @ self.basis).reshape(24, 24)

    def __call__(self, hx: float, hy: float, hz: float) -> np.ndarray:
        key = (hx, hy, hz)
        k = self._cache.get(key)
        if k is None:
            k = self._span(hx, hy, hz) if self.spanned else element_matrix(hx, hy, hz, self.mat)
            k = 0.5 * (k + k.T)
            self._cache[key] = k
        return k


def element_bound(ke: np.ndarray) -> float:
    """Upper bound of ``lambda_max(D^-1 K)`` for a grid of the element matrices ``ke`` (..., 24, 24).

    ``x.K x = sum_e x_e.K_e x_e <= max_e lambda_e sum_e x_e.D_e x_e = max_e lambda_e x.D x`` with
    ``lambda_e = lambda_max(D_e^-1 K_e)`` (``D_e`` the element's own diagonal; ``D = sum_e D_e``);
    it holds on any subspace (fixed dofs) and for the tied space of periodic faces. The smoother
    only needs an upper end of the spectrum, so no power iteration is needed where this is tight
    (the fine levels).
    """
    k = ke.reshape(-1, 24, 24)
    d = np.einsum("nii->ni", k)
    dc = d.reshape(-1, 8, 3)
    if np.abs(dc - dc[:, :1]).max() <= 1e-12 * np.abs(d).max() and modal_blocks(k)[3] <= MODAL_TOLERANCE:
        # a box: the diagonal is the same on every corner (per component), so D commutes with
        # the modal transform (F / sqrt 8 is orthogonal), and the matrix splits into its two
        # modal blocks: the bound is the larger of theirs (9 x 9 and 12 x 12 instead of 24 x 24)
        o = list(_MODAL_ORDER)
        s = 1.0 / np.sqrt(np.tile(dc[:, 0], 8))[:, o]
        kh = _to_modal(k)[:, o][:, :, o] / 8.0 * s[:, :, None] * s[:, None, :]
        return float(max(np.linalg.eigvalsh(kh[:, :9, :9])[:, -1].max(), np.linalg.eigvalsh(kh[:, 9:, 9:])[:, -1].max()))
    s = 1.0 / np.sqrt(d)
    return float(np.linalg.eigvalsh(k * s[:, :, None] * s[:, None, :])[:, -1].max())

# Modal form of a box element's matrix. On the 8 corners, per component, the
# Walsh-Hadamard transform gives the amplitudes of 1, xi, eta, xi eta, zeta,
# xi zeta, eta zeta, xi eta zeta (lexicographic corner bits x, y, z). For a
# box the translation rows vanish, and the one-point element's uniform-strain
# part (linear modes xi, eta, zeta) and its hourglass part (the four
# bilinear/trilinear modes, whose shape vectors are the bare hourglass
# vectors on a box) do not couple: K = F^T diag(KL, KH) F / 64 with a 9 x 9
# and a 12 x 12 block (225 multiply-adds and 2 x 72 additions per element
# instead of 576 multiply-adds), checked against the dense matrix at setup.

#: lexicographic index (bits x, y, z) of the solver's local corner I
_LEX = (0, 1, 3, 2, 4, 5, 7, 6)
#: lexicographic modes of the uniform-strain part (xi, eta, zeta) and of the hourglass part
_LIN_MODES = (1, 2, 4)
_HG_MODES = (3, 5, 6, 7)
#: largest coupling (relative to the largest entry) accepted outside the two blocks
MODAL_TOLERANCE = 1e-9


def modal_transform() -> np.ndarray:
    """``F`` (24 x 24): element dofs (local corner I x 3 components) to modal dofs (mode x 3).

    ``F[3 m + c, 3 I + c] = prod over the set bits b of m of (+1 if bit b of corner I's
    lexicographic index is set else -1)``; ``F F^T = 8 I`` per component (the butterflies of
    :func:`_wht`)."""
    F = np.zeros((24, 24))
    for m in range(8):
        for I in range(8):
            lex = _LEX[I]
            sgn = 1.0
            for b in range(3):
                if m >> b & 1:
                    sgn *= 1.0 if lex >> b & 1 else -1.0
            for c in range(3):
                F[3 * m + c, 3 * I + c] = sgn
    return F


#: modal dofs in the order of :func:`modal_blocks` (uniform-strain modes, then hourglass modes; x 3 components)
_MODAL_ORDER = tuple(3 * m + c for m in _LIN_MODES for c in range(3)) + tuple(3 * m + c for m in _HG_MODES
                                                                             for c in range(3))


def _to_modal(ke: np.ndarray) -> np.ndarray:
    """``F K F^T`` of element matrices ``ke`` (..., 24, 24), as (n, 24, 24)."""
    F = modal_transform()
    return F @ ke.reshape(-1, 24, 24) @ F.T


def modal_blocks(ke: np.ndarray):
    """Modal form of element matrices ``ke`` (..., 24, 24): ``(rows, cols, vals, coupling)``.

    Modal dofs: 0-8 the uniform-strain part (mode xi, eta, zeta x component), 9-20 the
    hourglass part (modes xi eta, xi zeta, eta zeta, xi eta zeta x component). ``rows, cols``
    (int64) list the entries of the two diagonal blocks that are not zero in any of the
    matrices (a box gives 21 + 24 of 81 + 144), ``vals`` (..., nnz) their values / 64;
    ``coupling`` is the largest entry left out (between the blocks, on the translations, or
    below 1e-13 of the largest) relative to the largest."""
    kh = _to_modal(ke)
    oi = np.array(_MODAL_ORDER)
    amax = np.abs(kh).max(axis=0)  # (24, 24): the largest of each entry over the matrices
    big = amax.max()
    keep = np.zeros((21, 21), dtype=bool)
    keep[:9, :9] = True
    keep[9:, 9:] = True
    keep &= amax[np.ix_(oi, oi)] > 1e-13 * big
    rows, cols = np.nonzero(keep)
    if set(zip(rows.tolist(), cols.tolist())) <= set(BOX_PATTERN):
        rows, cols = (np.array(a) for a in zip(*BOX_PATTERN))  # the written-out product (apply_k_box)
    left = amax.copy()
    left[oi[rows], oi[cols]] = 0.0
    vals = np.ascontiguousarray(kh[:, oi[rows], oi[cols]].reshape(*ke.shape[:-2], len(rows)) / 64.0)
    return rows.astype(np.int64), cols.astype(np.int64), vals, float(left.max() / big)


#: the nonzero entries (modal row, column) of a box element's two blocks, in :func:`modal_blocks`' order
BOX_PATTERN = ((0, 0), (0, 4), (0, 8), (1, 1), (1, 3), (2, 2), (2, 6), (3, 1), (3, 3), (4, 0), (4, 4), (4, 8), (5, 5), (5, 7), (6, 2), (6, 6), (7, 5), (7, 7), (8, 0), (8, 4), (8, 8), (9, 9), (9, 17), (10, 10), (10, 14), (11, 11), (11, 13), (11, 15), (12, 12), (12, 16), (13, 11), (13, 13), (13, 15), (14, 10), (14, 14), (15, 11), (15, 13), (15, 15), (16, 12), (16, 16), (17, 9), (17, 17), (18, 18), (19, 19), (20, 20))


@jit(inline="always")
def _wht(a0, a1, a2, a3, a4, a5, a6, a7):
    """Walsh-Hadamard transform of 8 corner values in lexicographic order (corners -> modes; the butterflies
    of :func:`modal_transform`)."""
    a0, a1, a2, a3, a4, a5, a6, a7 = a0 + a1, a1 - a0, a2 + a3, a3 - a2, a4 + a5, a5 - a4, a6 + a7, a7 - a6
    a0, a2, a1, a3, a4, a6, a5, a7 = a0 + a2, a2 - a0, a1 + a3, a3 - a1, a4 + a6, a6 - a4, a5 + a7, a7 - a5
    return a0 + a4, a1 + a5, a2 + a6, a3 + a7, a4 - a0, a5 - a1, a6 - a2, a7 - a3


@jit(inline="always")
def _wht_t(a0, a1, a2, a3, a4, a5, a6, a7):
    """Transpose of :func:`_wht` (modes -> lexicographic corners)."""
    a0, a4, a1, a5, a2, a6, a3, a7 = a0 - a4, a0 + a4, a1 - a5, a1 + a5, a2 - a6, a2 + a6, a3 - a7, a3 + a7
    a0, a2, a1, a3, a4, a6, a5, a7 = a0 - a2, a0 + a2, a1 - a3, a1 + a3, a4 - a6, a4 + a6, a5 - a7, a5 + a7
    return a0 - a1, a0 + a1, a2 - a3, a2 + a3, a4 - a5, a4 + a5, a6 - a7, a6 + a7


@jit(inline="always")
def _corners(u, n0, nnx, nnxy, c):
    """Component ``c`` of ``u`` on the 8 corners of the element at first node ``n0``, lexicographic."""
    return (u[n0, c], u[n0 + 1, c], u[n0 + nnx, c], u[n0 + 1 + nnx, c], u[n0 + nnxy, c], u[n0 + 1 + nnxy, c],
            u[n0 + nnx + nnxy, c], u[n0 + 1 + nnx + nnxy, c])


@jit(inline="always")
def _add_corners(out, n0, nnx, nnxy, c, o0, o1, o2, o3, o4, o5, o6, o7):
    """Add 8 corner values (lexicographic) to component ``c`` of ``out``."""
    out[n0, c] += o0
    out[n0 + 1, c] += o1
    out[n0 + nnx, c] += o2
    out[n0 + 1 + nnx, c] += o3
    out[n0 + nnxy, c] += o4
    out[n0 + 1 + nnxy, c] += o5
    out[n0 + nnx + nnxy, c] += o6
    out[n0 + 1 + nnx + nnxy, c] += o7


@jit
def apply_k_box(u, out, vals, tx, ty, tz, nnx, nny, nx, ny, nz, bc):
    """``out = K u`` (N), each element's matrix in modal form with its entries in :data:`BOX_PATTERN`
    (``vals`` in that order, :func:`modal_blocks`), written out: corners and modes in registers, no index
    lists; zero at fixed dofs (``bc`` bits). The references it is tested against:
    :mod:`peenflow.fe.box_stiffness_reference`."""
    nnxy = nnx * nny
    out[:, :] = 0.0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n0 = i + nnx * (j + nny * k)
                a0, a1, a2, a3, a4, a5, a6, a7 = _corners(u, n0, nnx, nnxy, 0)
                wx0, wx1, wx2, wx3, wx4, wx5, wx6, wx7 = _wht(a0, a1, a2, a3, a4, a5, a6, a7)
                a0, a1, a2, a3, a4, a5, a6, a7 = _corners(u, n0, nnx, nnxy, 1)
                wy0, wy1, wy2, wy3, wy4, wy5, wy6, wy7 = _wht(a0, a1, a2, a3, a4, a5, a6, a7)
                a0, a1, a2, a3, a4, a5, a6, a7 = _corners(u, n0, nnx, nnxy, 2)
                wz0, wz1, wz2, wz3, wz4, wz5, wz6, wz7 = _wht(a0, a1, a2, a3, a4, a5, a6, a7)
                m0 = wx1
                m1 = wy1
                m2 = wz1
                m3 = wx2
                m4 = wy2
                m5 = wz2
                m6 = wx4
                m7 = wy4
                m8 = wz4
                m9 = wx3
                m10 = wy3
                m11 = wz3
                m12 = wx5
                m13 = wy5
                m14 = wz5
                m15 = wx6
                m16 = wy6
                m17 = wz6
                m18 = wx7
                m19 = wy7
                m20 = wz7
                v = vals[tx[i], ty[j], tz[k]]
                y0 = v[0] * m0 + v[1] * m4 + v[2] * m8
                y1 = v[3] * m1 + v[4] * m3
                y2 = v[5] * m2 + v[6] * m6
                y3 = v[7] * m1 + v[8] * m3
                y4 = v[9] * m0 + v[10] * m4 + v[11] * m8
                y5 = v[12] * m5 + v[13] * m7
                y6 = v[14] * m2 + v[15] * m6
                y7 = v[16] * m5 + v[17] * m7
                y8 = v[18] * m0 + v[19] * m4 + v[20] * m8
                y9 = v[21] * m9 + v[22] * m17
                y10 = v[23] * m10 + v[24] * m14
                y11 = v[25] * m11 + v[26] * m13 + v[27] * m15
                y12 = v[28] * m12 + v[29] * m16
                y13 = v[30] * m11 + v[31] * m13 + v[32] * m15
                y14 = v[33] * m10 + v[34] * m14
                y15 = v[35] * m11 + v[36] * m13 + v[37] * m15
                y16 = v[38] * m12 + v[39] * m16
                y17 = v[40] * m9 + v[41] * m17
                y18 = v[42] * m18
                y19 = v[43] * m19
                y20 = v[44] * m20
                o0, o1, o2, o3, o4, o5, o6, o7 = _wht_t(0.0, y0, y3, y9, y6, y12, y15, y18)
                _add_corners(out, n0, nnx, nnxy, 0, o0, o1, o2, o3, o4, o5, o6, o7)
                o0, o1, o2, o3, o4, o5, o6, o7 = _wht_t(0.0, y1, y4, y10, y7, y13, y16, y19)
                _add_corners(out, n0, nnx, nnxy, 1, o0, o1, o2, o3, o4, o5, o6, o7)
                o0, o1, o2, o3, o4, o5, o6, o7 = _wht_t(0.0, y2, y5, y11, y8, y14, y17, y20)
                _add_corners(out, n0, nnx, nnxy, 2, o0, o1, o2, o3, o4, o5, o6, o7)
    mask_fixed(out, bc)


@jit
def inverse_diagonal(ke, tx, ty, tz, nnx, nny, nx, ny, nz, bc, d):
    """``d`` (n_nodes, 3) = 1 / the diagonal of ``K`` (m/N), 0 at fixed dofs (``bc`` bits): the
    Jacobi scaling of the multigrid's smoother."""
    nnxy = nnx * nny
    offs = (0, 1, 1 + nnx, nnx, nnxy, nnxy + 1, nnxy + 1 + nnx, nnxy + nnx)
    d[:, :] = 0.0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n0 = i + nnx * (j + nny * k)
                K = ke[tx[i], ty[j], tz[k]]
                for I in range(8):
                    for c in range(3):
                        d[n0 + offs[I], c] += K[3 * I + c, 3 * I + c]
    for n in range(d.shape[0]):
        for c in range(3):
            if bc[n] & (1 << c):
                d[n, c] = 0.0
            else:
                d[n, c] = 1.0 / d[n, c]
