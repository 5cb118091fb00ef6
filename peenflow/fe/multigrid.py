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

Element stiffness. Every level uses the solver's own element at the
reference geometry, its matrices and the product ``K u`` from
:mod:`peenflow.fe.box_stiffness` (probed from the element pass, combined
from six probed boxes, applied in modal form).

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
from peenflow.fe.boundary import TIED, mask_fixed, tied_master
from peenflow.fe.box_stiffness import (BOX_PATTERN, MODAL_TOLERANCE, ElementMatrices, apply_k_box, element_bound,
                                       inverse_diagonal, modal_blocks)

COARSEST_NODES = 600
CHEB_DEGREE = 2
CHEB_RATIO = 15.0
POWER_ITERATIONS = 30
#: levels with more nodes than this bound lambda_max(D^-1 K) by their elements' instead (:func:`element_bound`)
POWER_MAX_NODES = 20_000


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
    modal: tuple = ()  # (rows, cols, vals): the element matrices in the box element's modal blocks

    def _apply_box(self, u, out):
        apply_k_box(u, out, self.modal[2], *self.types, self.nn[0], self.nn[1], *self.ne, self.bc)

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
            inverse_diagonal(ke, *types, nn[0], nn[1], *ne, np.zeros_like(bc), dinv)
            d = 1.0 / dinv
            fold_tied(d, bc, nn[0], nn[1])
            free = d != 0.0
            dinv = np.where(free, 1.0 / np.where(free, d, 1.0), 0.0)
            mask_fixed(dinv, bc)
        else:
            inverse_diagonal(ke, *types, nn[0], nn[1], *ne, bc, dinv)
        rows, cols, vals, coupling = modal_blocks(ke)
        if coupling > MODAL_TOLERANCE or len(rows) != len(BOX_PATTERN):
            # the solver's element on a box (either hourglass form) always has that form
            raise ValueError(
                f"multigrid: element matrices not of the box element's modal form (coupling {coupling:.2e} of the "
                f"largest entry outside its blocks, {len(rows)} block entries for {len(BOX_PATTERN)}); the "
                "multigrid applies only that form (peenflow.fe.box_stiffness_reference has the general products)")
        modal = (rows, cols, vals)
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
