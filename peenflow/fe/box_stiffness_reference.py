"""Reference products of :mod:`peenflow.fe.box_stiffness`: ``K u`` written plainly, for the tests.

The multigrid applies each box element in the written-out modal form
(:func:`peenflow.fe.box_stiffness.apply_k_box`). This module keeps the same
operator two more ways, which tests/fe/test_relaxation.py compares it
against (to 1e-13 on every level, both hourglass forms): the dense 24 x 24
element matrices (:func:`apply_k`) and the modal form with the index lists of
:func:`peenflow.fe.box_stiffness.modal_blocks` (:func:`apply_k_modal`, any
block pattern). The solver never calls them.
"""

from __future__ import annotations

import numpy as np

from peenflow._jit import jit
from peenflow.fe.boundary import mask_fixed
from peenflow.fe.box_stiffness import _HG_MODES, _LEX, _LIN_MODES
from peenflow.fe.element import corner_offsets


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
