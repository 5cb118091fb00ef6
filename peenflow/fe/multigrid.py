"""Geometric multigrid for the linear elastic correction on the structured box mesh.

Used by the static global relaxation (:mod:`peenflow.fe.relaxation`) as an
approximate inverse of the target's stiffness: ``solve(r) ~= K^-1 r`` for a
nodal force imbalance ``r`` (n_nodes, 3) N, returning a displacement
correction (n_nodes, 3) m. The relaxation itself always evaluates the true
nonlinear forces with the solver's element pass; this module only has to be a
good *preconditioner*, so it works on the undeformed (reference) box
geometry and linear elasticity.

Levels. Level 0 is the mesh: a tensor grid of axis-aligned box elements
(``BoxMesh``). Each coarser level keeps a subset of the nodes along each
axis, so coarse nodes are fine nodes and the boundary conditions carry over
node by node: consecutive intervals are merged in pairs as long as the pair
is no longer than twice the largest median spacing of the three axes
(:func:`_coarse_indices`). A graded axis is therefore only coarsened where
its elements are thin: the deep graded layers (25 um wide, up to 170 um
tall) are kept until the lateral spacing has caught up, which keeps the
coarse elements near-cubic (point smoothers fail on strongly anisotropic
elements; plain every-other-node coarsening stalled CG at 200 iterations on
the strip REV). Coarsening stops at <= ``COARSEST_NODES`` nodes, solved
exactly (dense inverse).

Element stiffness. Every level uses the solver's own element (one-point
hexahedron + Flanagan-Belytschko stiffness hourglass control, same
``mat`` vector), its 24 x 24 matrix *probed* from
:func:`peenflow.fe.element.element_rows` on a single box element (unit
displacement of each of the 24 dofs, tiny amplitude, huge step so bulk
viscosity vanishes), so level 0 is exactly the tangent of the solver's
element at the reference geometry, whatever the element's internal
conventions. A tensor grid has few distinct element sizes (``hx``, ``hy``,
``hz`` per axis), so one matrix per distinct (hx, hy, hz) is stored; they
are combined from six probed boxes (:class:`ElementMatrices`, checked
against direct probes). The operator applies each element in modal form
(Walsh-Hadamard transform of its corners, then the 21 + 24 nonzero entries
of the box element's uniform-strain and hourglass blocks, written out in
:func:`apply_k_box`; :func:`apply_k_modal` with index lists for any other
pattern): the same operator as the dense 24 x 24 product to round-off,
4x faster (docs/performance.md section 3, "Multigrid setup").

Cycle. Symmetric V-cycle: Chebyshev smoothing (polynomial in D^-1 K over
``[hi / CHEB_RATIO, hi]``, ``hi = 1.15 lambda_max``, ``lambda_max`` by power
iteration; on levels of more than ``POWER_MAX_NODES`` nodes ``hi`` is a
guaranteed element-wise bound instead, :func:`element_bound`) before and
after the coarse correction, trilinear prolongation, restriction = its
transpose. As a preconditioner for conjugate gradients
(:func:`pcg`) it is symmetric positive definite.

Periodic lateral faces (``periodic=True``; slave nodes flagged in ``bc``,
:mod:`peenflow.fe.boundary`): every level works on master-only vectors
(slave entries 0) with ``K_p = T^T K T`` (``T`` copies each master to its
slaves): apply = unfold, box ``K``, fold; Jacobi diagonal = a master's plus
its slaves'; restriction folds the coarse residual, prolongation unfolds the
coarse correction first. Every level keeps both end nodes of each axis, so
the coarse grids are periodic in the same way; the cycle stays SPD.

All loops are serial and in a fixed order: results do not depend on the
numba thread count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from peenflow._jit import jit
from peenflow.fe.boundary import TIED, tied_master
from peenflow.fe.element import corner_offsets, element_rows

COARSEST_NODES = 600
CHEB_DEGREE = 2
CHEB_RATIO = 15.0
POWER_ITERATIONS = 30
#: levels with more nodes than this bound lambda_max(D^-1 K) by their elements' instead (:func:`element_bound`)
POWER_MAX_NODES = 20_000

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


def _unique_spacing(axis: np.ndarray):
    """(type index per interval, distinct spacings) with a relative tolerance of 1e-9."""
    h = np.diff(axis)
    vals: list[float] = []
    idx = np.empty(len(h), dtype=np.int64)
    for n, s in enumerate(h):
        for t, u in enumerate(vals):
            if abs(s - u) <= 1e-9 * u:
                idx[n] = t
                break
        else:
            idx[n] = len(vals)
            vals.append(float(s))
    return idx, np.array(vals)


def _pairs(h: np.ndarray, target: float) -> list:
    """Group sizes (1, 2 or 3) for intervals ``h`` taken in order: pairs while
    the pair is no longer than ``target``; a single interval left at the end
    after a pair joins it if the three stay below 1.5 ``target``."""
    groups = []
    i = 0
    while i < len(h):
        if i + 1 < len(h) and h[i] + h[i + 1] <= target * (1 + 1e-9):
            groups.append(2)
            i += 2
        else:
            groups.append(1)
            i += 1
    if len(groups) >= 2 and groups[-1] == 1 and groups[-2] == 2 and h[-3:].sum() <= 1.5 * target:
        groups[-2:] = [3]
    return groups


def _coarse_indices(axis: np.ndarray, target: float) -> np.ndarray:
    """Nodes of an axis kept on the next level (see :func:`_pairs`).

    An axis symmetric about its midpoint is grouped from both ends towards
    the middle, so the hierarchy keeps the mesh's mirror symmetry (a centred
    impact then relaxes to a mirror-symmetric field to round-off)."""
    h = np.diff(axis)
    n = len(h)
    if np.allclose(h, h[::-1], rtol=1e-9, atol=0.0):
        half = n // 2
        left = _pairs(h[:half], target)
        groups = left + ([1] if n % 2 else []) + left[::-1]
    else:
        groups = _pairs(h, target)
    return np.concatenate([[0], np.cumsum(groups)]).astype(np.int64)


def _interp(fine: np.ndarray, coarse: np.ndarray):
    """Linear interpolation on an axis: fine node -> (c0, c1, weight of c1)."""
    c1 = np.clip(np.searchsorted(coarse, fine, side="left"), 1, len(coarse) - 1)
    c0 = c1 - 1
    w = (fine - coarse[c0]) / (coarse[c1] - coarse[c0])
    w = np.where(np.abs(w) < 1e-12, 0.0, np.where(np.abs(w - 1.0) < 1e-12, 1.0, w))
    return c0.astype(np.int64), c1.astype(np.int64), w


@jit
def apply_k(u, out, ke, tx, ty, tz, nnx, nny, nx, ny, nz, bc):
    """``out = K u`` (N) for the box-element grid; zero at fixed dofs (``bc`` bits)."""
    offs = corner_offsets(nnx, nnx * nny)
    out[:, :] = 0.0
    ul = np.empty(24)  # the element's 24 dofs, corner by corner
    fl = np.empty(24)
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n0 = i + nnx * (j + nny * k)
                for I in range(8):
                    n = n0 + offs[I]
                    ul[3 * I] = u[n, 0]
                    ul[3 * I + 1] = u[n, 1]
                    ul[3 * I + 2] = u[n, 2]
                K = ke[tx[i], ty[j], tz[k]]
                for a in range(24):
                    fl[a] = 0.0
                for b in range(24):
                    ub = ul[b]
                    for a in range(24):
                        fl[a] += K[b, a] * ub
                for I in range(8):
                    n = n0 + offs[I]
                    out[n, 0] += fl[3 * I]
                    out[n, 1] += fl[3 * I + 1]
                    out[n, 2] += fl[3 * I + 2]
    mask_fixed(out, bc)


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
    :func:`apply_k_modal`)."""
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


@jit(inline="always")
def _butterflies(w):
    """Walsh-Hadamard transform of 8 corner values in lexicographic order, in place."""
    for p in (0, 2, 4, 6):
        a = w[p]
        b = w[p + 1]
        w[p] = a + b
        w[p + 1] = b - a
    for p in (0, 1, 4, 5):
        a = w[p]
        b = w[p + 2]
        w[p] = a + b
        w[p + 2] = b - a
    for p in (0, 1, 2, 3):
        a = w[p]
        b = w[p + 4]
        w[p] = a + b
        w[p + 4] = b - a


@jit(inline="always")
def _butterflies_t(w):
    """Transpose of :func:`_butterflies`, in place."""
    for p in (0, 1, 2, 3):
        s = w[p]
        d = w[p + 4]
        w[p] = s - d
        w[p + 4] = s + d
    for p in (0, 1, 4, 5):
        s = w[p]
        d = w[p + 2]
        w[p] = s - d
        w[p + 2] = s + d
    for p in (0, 2, 4, 6):
        s = w[p]
        d = w[p + 1]
        w[p] = s - d
        w[p + 1] = s + d


@jit
def apply_k_modal(u, out, rows, cols, vals, tx, ty, tz, nnx, nny, nx, ny, nz, bc):
    """``out = K u`` (N) like :func:`apply_k`, with each element's matrix in modal form
    (``rows, cols, vals`` from :func:`modal_blocks`)."""
    offs = corner_offsets(nnx, nnx * nny)
    nnz = len(rows)
    out[:, :] = 0.0
    w = np.empty(8)  # one component's 8 corner values, lexicographic
    xm = np.empty(21)  # modal amplitudes in, out
    ym = np.empty(21)
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n0 = i + nnx * (j + nny * k)
                for c in range(3):
                    for I in range(8):
                        w[_LEX[I]] = u[n0 + offs[I], c]
                    _butterflies(w)
                    for a in range(3):
                        xm[3 * a + c] = w[_LIN_MODES[a]]
                    for b in range(4):
                        xm[9 + 3 * b + c] = w[_HG_MODES[b]]
                for a in range(21):
                    ym[a] = 0.0
                v = vals[tx[i], ty[j], tz[k]]
                for t in range(nnz):
                    ym[rows[t]] += v[t] * xm[cols[t]]
                for c in range(3):
                    w[0] = 0.0
                    for a in range(3):
                        w[_LIN_MODES[a]] = ym[3 * a + c]
                    for b in range(4):
                        w[_HG_MODES[b]] = ym[9 + 3 * b + c]
                    _butterflies_t(w)
                    for I in range(8):
                        out[n0 + offs[I], c] += w[_LEX[I]]
    mask_fixed(out, bc)


#: the nonzero entries (modal row, column) of a box element's two blocks, in :func:`modal_blocks`' order
BOX_PATTERN = ((0, 0), (0, 4), (0, 8), (1, 1), (1, 3), (2, 2), (2, 6), (3, 1), (3, 3), (4, 0), (4, 4), (4, 8), (5, 5), (5, 7), (6, 2), (6, 6), (7, 5), (7, 7), (8, 0), (8, 4), (8, 8), (9, 9), (9, 17), (10, 10), (10, 14), (11, 11), (11, 13), (11, 15), (12, 12), (12, 16), (13, 11), (13, 13), (13, 15), (14, 10), (14, 14), (15, 11), (15, 13), (15, 15), (16, 12), (16, 16), (17, 9), (17, 17), (18, 18), (19, 19), (20, 20))


@jit(inline="always")
def _wht(a0, a1, a2, a3, a4, a5, a6, a7):
    """:func:`_butterflies` on 8 scalars (lexicographic corners -> modes)."""
    a0, a1, a2, a3, a4, a5, a6, a7 = a0 + a1, a1 - a0, a2 + a3, a3 - a2, a4 + a5, a5 - a4, a6 + a7, a7 - a6
    a0, a2, a1, a3, a4, a6, a5, a7 = a0 + a2, a2 - a0, a1 + a3, a3 - a1, a4 + a6, a6 - a4, a5 + a7, a7 - a5
    return a0 + a4, a1 + a5, a2 + a6, a3 + a7, a4 - a0, a5 - a1, a6 - a2, a7 - a3


@jit(inline="always")
def _wht_t(a0, a1, a2, a3, a4, a5, a6, a7):
    """:func:`_butterflies_t` on 8 scalars (modes -> lexicographic corners)."""
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
    """:func:`apply_k_modal` for matrices whose entries lie in :data:`BOX_PATTERN` (``vals`` in
    that order), written out: corners and modes in registers, no index lists."""
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
def _diagonal(ke, tx, ty, tz, nnx, nny, nx, ny, nz, bc, d):
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


@jit(inline="always")
def _coarse_corner(q, i, j, k, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nncx, nncy):
    """Corner ``q`` (0..7, bits: x, y, z) of the coarse cell around fine node (i, j, k):
    ``(coarse node index, trilinear weight)``; the weight is 0 for a corner not used."""
    ii = q & 1
    jj = (q >> 1) & 1
    kk = q >> 2
    ci = cx1[i] if ii else cx0[i]
    wi = wx[i] if ii else 1.0 - wx[i]
    cj = cy1[j] if jj else cy0[j]
    wj = wy[j] if jj else 1.0 - wy[j]
    ck = cz1[k] if kk else cz0[k]
    wk = wz[k] if kk else 1.0 - wz[k]
    return ci + nncx * (cj + nncy * ck), wi * wj * wk


@jit
def _prolong_add(uc, uf, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nncx, nncy, bc):
    """``uf += P uc`` (trilinear on the tensor grid); fixed dofs untouched."""
    nfx = cx0.shape[0]
    nfy = cy0.shape[0]
    nfz = cz0.shape[0]
    for k in range(nfz):
        for j in range(nfy):
            for i in range(nfx):
                n = i + nfx * (j + nfy * k)
                s0 = 0.0
                s1 = 0.0
                s2 = 0.0
                for q in range(8):
                    m, w = _coarse_corner(q, i, j, k, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nncx, nncy)
                    if w == 0.0:
                        continue
                    s0 += w * uc[m, 0]
                    s1 += w * uc[m, 1]
                    s2 += w * uc[m, 2]
                b = bc[n]
                if not (b & 1):
                    uf[n, 0] += s0
                if not (b & 2):
                    uf[n, 1] += s1
                if not (b & 4):
                    uf[n, 2] += s2


@jit
def _restrict(rf, rc, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nncx, nncy, bcc):
    """``rc = P^T rf``; zero at the coarse level's fixed dofs."""
    nfx = cx0.shape[0]
    nfy = cy0.shape[0]
    nfz = cz0.shape[0]
    rc[:, :] = 0.0
    for k in range(nfz):
        for j in range(nfy):
            for i in range(nfx):
                n = i + nfx * (j + nfy * k)
                r0 = rf[n, 0]
                r1 = rf[n, 1]
                r2 = rf[n, 2]
                for q in range(8):
                    m, w = _coarse_corner(q, i, j, k, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nncx, nncy)
                    if w == 0.0:
                        continue
                    rc[m, 0] += w * r0
                    rc[m, 1] += w * r1
                    rc[m, 2] += w * r2
    mask_fixed(rc, bcc)


@jit
def _cheb_update(d, r, dinv, x, c_old, c_new):
    """``d = c_old d + c_new D^-1 r;  x += d`` (fused)."""
    for n in range(d.shape[0]):
        for c in range(3):
            dn = c_old * d[n, c] + c_new * dinv[n, c] * r[n, c]
            d[n, c] = dn
            x[n, c] += dn


@jit
def _axpy(y, a, x):
    for n in range(y.shape[0]):
        for c in range(3):
            y[n, c] += a * x[n, c]


@jit
def fold_tied(r, bc, nnx, nny):
    """Periodic slaves (``bc`` bits 8 / 16, :mod:`peenflow.fe.boundary`): add each
    slave's entry of ``r`` to its master's and zero it (in place)."""
    for n in range(r.shape[0]):
        b = bc[n]
        if b & TIED:
            m = tied_master(n, b, nnx, nny)
            for c in range(3):
                r[m, c] += r[n, c]
                r[n, c] = 0.0


@jit
def unfold_tied(u, bc, nnx, nny):
    """Periodic slaves: copy each master's entry of ``u`` to its slaves (in place)."""
    for n in range(u.shape[0]):
        b = bc[n]
        if b & TIED:
            m = tied_master(n, b, nnx, nny)
            for c in range(3):
                u[n, c] = u[m, c]


@jit
def _mask_tied(r, bc):
    for n in range(r.shape[0]):
        if bc[n] & TIED:
            r[n, 0] = 0.0
            r[n, 1] = 0.0
            r[n, 2] = 0.0


@jit
def mask_fixed(r, bc):
    """Zero the fixed dofs (``bc`` bits) of ``r`` (n_nodes, 3) in place."""
    for n in range(r.shape[0]):
        b = bc[n]
        for c in range(3):
            if b & (1 << c):
                r[n, c] = 0.0


@jit
def dot(a, b):
    s = 0.0
    for n in range(a.shape[0]):
        for c in range(3):
            s += a[n, c] * b[n, c]
    return s


@dataclass
class Level:
    """One grid level: node axes (m), element tables, fixities, smoother data."""

    axes: tuple
    nn: tuple
    ne: tuple
    types: tuple
    ke: np.ndarray
    bc: np.ndarray
    dinv: np.ndarray
    lam_max: float = 1.0
    interp: tuple | None = None  # prolongation from the next coarser level (cx0, cx1, wx, cy0, ...)
    coarse_inv: np.ndarray | None = None  # dense inverse on the coarsest level
    periodic: bool = False  # tied lateral faces: vectors live on the masters (slaves 0)
    modal: tuple | None = None  # (rows, cols, vals) when the element matrices split into modal blocks

    def _apply_box(self, u, out):
        if self.modal is not None and len(self.modal[0]) == len(BOX_PATTERN):
            apply_k_box(u, out, self.modal[2], *self.types, self.nn[0], self.nn[1], *self.ne, self.bc)
        elif self.modal is not None:
            apply_k_modal(u, out, *self.modal, *self.types, self.nn[0], self.nn[1], *self.ne, self.bc)
        else:
            apply_k(u, out, self.ke, *self.types, self.nn[0], self.nn[1], *self.ne, self.bc)

    def apply(self, u, out):
        if self.periodic:
            # K_p = T^T K T on master-only vectors: unfold, apply the box's K, fold
            uc = u.copy()
            unfold_tied(uc, self.bc, self.nn[0], self.nn[1])
            self._apply_box(uc, out)
            fold_tied(out, self.bc, self.nn[0], self.nn[1])
        else:
            self._apply_box(u, out)


class Multigrid:
    """Hierarchy for a ``BoxMesh`` with node fixities ``bc`` and material vector ``mat``."""

    def __init__(self, mesh, bc: np.ndarray, mat: np.ndarray, periodic: bool = False):
        axes = (np.asarray(mesh.x, float), np.asarray(mesh.y, float), np.asarray(mesh.z, float))
        bc3 = np.asarray(bc).reshape(len(axes[2]), len(axes[1]), len(axes[0]))
        self.periodic = periodic
        self.levels: list[Level] = []
        ematrix = ElementMatrices(mat, float(np.median(np.concatenate([np.diff(a) for a in axes]))))
        while True:
            # every level keeps both end nodes of each axis, so the slaves' bits carry over
            lev = self._level(axes, bc3, ematrix, periodic)
            self.levels.append(lev)
            n = lev.nn[0] * lev.nn[1] * lev.nn[2]
            target = 2.0 * max(float(np.median(np.diff(a))) for a in axes)
            idx = [_coarse_indices(a, target) for a in axes]
            if n <= COARSEST_NODES or all(len(i) == len(a) for i, a in zip(idx, axes)):
                break
            caxes = tuple(a[i] for a, i in zip(axes, idx))
            interp = []
            for a, ca in zip(axes, caxes):
                interp.extend(_interp(a, ca))
            lev.interp = tuple(interp)
            bc3 = bc3[np.ix_(idx[2], idx[1], idx[0])]
            axes = caxes
        self._setup_smoothers()
        self._setup_coarsest()

    @staticmethod
    def _level(axes, bc3, ematrix, periodic=False) -> Level:
        types, spacings = zip(*(_unique_spacing(a) for a in axes))
        ke = np.zeros((len(spacings[0]), len(spacings[1]), len(spacings[2]), 24, 24))
        for a, hx in enumerate(spacings[0]):
            for b, hy in enumerate(spacings[1]):
                for c, hz in enumerate(spacings[2]):
                    ke[a, b, c] = ematrix(hx, hy, hz)
        nn = tuple(len(a) for a in axes)
        ne = tuple(n - 1 for n in nn)
        bc = np.ascontiguousarray(bc3.ravel())
        dinv = np.zeros((nn[0] * nn[1] * nn[2], 3))
        if periodic:
            # diagonal of T^T K T: a master's plus its slaves'; slaves (and fixed dofs) 0
            _diagonal(ke, *types, nn[0], nn[1], *ne, np.zeros_like(bc), dinv)
            d = 1.0 / dinv
            fold_tied(d, bc, nn[0], nn[1])
            free = d != 0.0
            dinv = np.where(free, 1.0 / np.where(free, d, 1.0), 0.0)
            mask_fixed(dinv, bc)
        else:
            _diagonal(ke, *types, nn[0], nn[1], *ne, bc, dinv)
        rows, cols, vals, coupling = modal_blocks(ke)
        modal = (rows, cols, vals) if coupling <= MODAL_TOLERANCE else None
        return Level(axes, nn, ne, tuple(types), ke, bc, dinv, periodic=periodic, modal=modal)

    def _setup_smoothers(self):
        for lev in self.levels[:-1]:
            n = lev.dinv.shape[0]
            if n > POWER_MAX_NODES:
                # fine levels: the smoother's upper end (1.15 x the estimate) is the guaranteed
                # bound itself, at no apply (30 applies per level before: ~0.8 s on a graded
                # 104 k-element block); it is within 5-10 % of the power estimate there
                # (1.045 and 1.095 times it on that block's two fine levels)
                lev.lam_max = element_bound(lev.ke) / 1.15
                continue
            # deterministic start vector
            u = np.cos(np.arange(3 * n, dtype=np.float64).reshape(n, 3) * 0.7) * (lev.dinv != 0)
            ku = np.empty_like(u)
            lam = 1.0
            for _ in range(POWER_ITERATIONS):
                u /= np.sqrt(dot(u, u))
                lev.apply(u, ku)
                z = lev.dinv * ku
                lam = np.sqrt(dot(z, z))
                u = z
            lev.lam_max = float(lam)

    def _setup_coarsest(self):
        lev = self.levels[-1]
        n = lev.dinv.shape[0]
        A = np.zeros((3 * n, 3 * n))
        e = np.zeros((n, 3))
        out = np.empty((n, 3))
        for d in range(3 * n):
            e.flat[d] = 1.0
            lev.apply(e, out)
            A[:, d] = out.ravel()
            e.flat[d] = 0.0
        fixed = (lev.dinv.ravel() == 0)
        A[fixed, :] = 0.0
        A[:, fixed] = 0.0
        A[fixed, fixed] = 1.0
        A = 0.5 * (A + A.T)
        Ainv = np.linalg.inv(A)
        Ainv[fixed, :] = 0.0
        Ainv[:, fixed] = 0.0
        lev.coarse_inv = 0.5 * (Ainv + Ainv.T)

    @property
    def n_levels(self) -> int:
        return len(self.levels)

    def _smooth(self, lev: Level, b, x, r, degree, x_zero, residual=True):
        """Chebyshev smoothing of ``K x = b``; ``r`` returns ``b - K x`` (if ``residual``;
        otherwise ``r`` is scratch and the last operator apply is skipped)."""
        hi = 1.15 * lev.lam_max
        lo = hi / CHEB_RATIO
        theta = 0.5 * (hi + lo)
        delta = 0.5 * (hi - lo)
        sigma = theta / delta
        rho = 1.0 / sigma
        kx = np.empty_like(x)
        if x_zero:
            r[:] = b
        else:
            lev.apply(x, kx)
            np.subtract(b, kx, out=r)
        d = np.zeros_like(x)
        _cheb_update(d, r, lev.dinv, x, 0.0, 1.0 / theta)
        for _ in range(degree - 1):
            lev.apply(d, kx)
            _axpy(r, -1.0, kx)
            rho_new = 1.0 / (2.0 * sigma - rho)
            _cheb_update(d, r, lev.dinv, x, rho_new * rho, 2.0 * rho_new / delta)
            rho = rho_new
        if residual:
            lev.apply(d, kx)
            _axpy(r, -1.0, kx)

    def vcycle(self, b: np.ndarray, level: int = 0) -> np.ndarray:
        """One symmetric V-cycle from ``x = 0``: an SPD approximation of ``K^-1 b``."""
        lev = self.levels[level]
        if level == len(self.levels) - 1:
            return (lev.coarse_inv @ b.ravel()).reshape(b.shape)
        x = np.zeros_like(b)
        r = np.empty_like(b)
        self._smooth(lev, b, x, r, CHEB_DEGREE, True)
        nxt = self.levels[level + 1]
        rc = np.empty((nxt.dinv.shape[0], 3))
        cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz = lev.interp
        _restrict(r, rc, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nxt.nn[0], nxt.nn[1], nxt.bc)
        if self.periodic:
            fold_tied(rc, nxt.bc, nxt.nn[0], nxt.nn[1])
        xc = self.vcycle(rc, level + 1)
        if self.periodic:
            # P on the tied space: prolong the unfolded coarse vector, keep the fine masters
            unfold_tied(xc, nxt.bc, nxt.nn[0], nxt.nn[1])
            xs = np.zeros_like(x)
            _prolong_add(xc, xs, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nxt.nn[0], nxt.nn[1], lev.bc)
            mask_fixed(xs, lev.bc)
            _mask_tied(xs, lev.bc)
            x += xs
        else:
            _prolong_add(xc, x, cx0, cx1, wx, cy0, cy1, wy, cz0, cz1, wz, nxt.nn[0], nxt.nn[1], lev.bc)
        # post-smoothing: its final residual is not used (one apply per level saved, same x)
        self._smooth(lev, b, x, r, CHEB_DEGREE, False, residual=False)
        return x


def pcg(mg: Multigrid, b: np.ndarray, *, rtol: float, max_iter: int = 200, z0: np.ndarray | None = None):
    """Conjugate gradients on level 0's ``K u = b``, preconditioned by one V-cycle.

    Stops when ``|r| <= rtol |b|`` (Euclidean norms of the free dofs).
    ``z0``: ``mg.vcycle(b)`` if the caller has it already.
    Returns ``(u, iterations, |r| / |b|)``.
    """
    lev = mg.levels[0]
    u = np.zeros_like(b)
    r = b.copy()
    nb = np.sqrt(dot(b, b))
    if nb == 0.0:
        return u, 0, 0.0
    z = mg.vcycle(r) if z0 is None else z0
    p = z.copy()
    rz = dot(r, z)
    kp = np.empty_like(b)
    it = 0
    rel = 1.0
    for it in range(1, max_iter + 1):
        lev.apply(p, kp)
        alpha = rz / dot(p, kp)
        _axpy(u, alpha, p)
        _axpy(r, -alpha, kp)
        rel = np.sqrt(dot(r, r)) / nb
        if rel <= rtol:
            break
        z = mg.vcycle(r)
        rz_new = dot(r, z)
        p *= rz_new / rz
        p += z
        rz = rz_new
    return u, it, rel
