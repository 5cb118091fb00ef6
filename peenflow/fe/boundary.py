"""Boundary conditions as per-node fixity bit masks.

Bit 0/1/2 set = the x/y/z velocity of the node is held at zero.

* bottom face (``z = z_max``): ``"fixed"`` (all three components; the
  paper's "embedding" condition) or ``"free"``;
* lateral faces: ``"symmetric"`` -- zero normal displacement (x-faces hold x,
  y-faces hold y), as in the paper (§4.1, §5) -- ``"free"``, or
  ``"periodic"``: the node ``i = nnx - 1`` is the image of ``i = 0`` (same
  ``j, k``) shifted by the period ``Lx = x[-1] - x[0]``, likewise ``j``
  (period ``Ly``); the corner column chains to ``(0, 0)``. Such a *slave*
  node carries the bit ``TIE_X`` and/or ``TIE_Y`` instead of a fixity; its
  master is ``n - TIE_X*(nnx - 1) - TIE_Y*nnx*(nny - 1)`` (bits read as 0/1).
  The solver folds a slave's force into its master, moves the master with
  their combined mass and copies its velocity (position + period) to the
  slave (:func:`peenflow.fe.solver._node_update`). The period is fixed: no
  mean in-plane strain of the cell, as with symmetric faces.

A quarter model (shot at a corner, symmetric faces through the impact point)
is just a box whose ``x_min`` and ``y_min`` faces are symmetric planes; the
driver detects shots centred on such planes and uses the matching fraction of
the shot's mass (:mod:`peenflow.fe.shots`).
"""

from __future__ import annotations

import numpy as np

from peenflow._jit import jit
from peenflow.fe.mesh import BoxMesh

FIX_X, FIX_Y, FIX_Z = 1, 2, 4
#: periodic slave node: image of the node ``nnx - 1`` columns before it (TIE_X) / ``nny - 1`` rows (TIE_Y)
TIE_X, TIE_Y = 8, 16
TIED = TIE_X | TIE_Y


@jit(inline="always")
def tied_master(n, b, nnx, nny):
    """The master node of periodic slave ``n`` whose bits are ``b`` (``b & TIED`` nonzero)."""
    m = n
    if b & TIE_X:
        m -= nnx - 1
    if b & TIE_Y:
        m -= nnx * (nny - 1)
    return m


@jit
def mask_fixed(r, bc):
    """Zero the fixed dofs (``bc`` bits) of ``r`` (n_nodes, 3) in place."""
    for n in range(r.shape[0]):
        b = bc[n]
        for c in range(3):
            if b & (1 << c):
                r[n, c] = 0.0


_LATERAL = ("symmetric", "free", "periodic")
_BOTTOM = ("fixed", "free")


def node_fixity(mesh: BoxMesh, lateral: str = "symmetric", bottom: str = "fixed") -> np.ndarray:
    """Per-node fixity masks, (n_nodes,) int8 (bits FIX_X | FIX_Y | FIX_Z)."""
    if lateral not in _LATERAL or bottom not in _BOTTOM:
        raise ValueError(f"lateral must be one of {_LATERAL}, bottom one of {_BOTTOM}")
    nnx, nny, nnz = mesh.shape_nodes
    bc = np.zeros((nnz, nny, nnx), dtype=np.int8)
    if lateral == "symmetric":
        bc[:, :, 0] |= FIX_X
        bc[:, :, -1] |= FIX_X
        bc[:, 0, :] |= FIX_Y
        bc[:, -1, :] |= FIX_Y
    if lateral == "periodic":
        bc[:, :, -1] |= TIE_X
        bc[:, -1, :] |= TIE_Y
    if bottom == "fixed":
        bc[-1, :, :] |= FIX_X | FIX_Y | FIX_Z
    return bc.ravel()
