"""Boundary conditions as per-node fixity bit masks.

Bit 0/1/2 set = the x/y/z velocity of the node is held at zero.

* bottom face (``z = z_max``): ``"fixed"`` (all three components; the
  paper's "embedding" condition) or ``"free"``;
* lateral faces: ``"symmetric"`` -- zero normal displacement (x-faces hold x,
  y-faces hold y), as in the paper (§4.1, §5) -- or ``"free"``.

A quarter model (shot at a corner, symmetric faces through the impact point)
is just a box whose ``x_min`` and ``y_min`` faces are symmetric planes; the
driver detects shots centred on such planes and uses the matching fraction of
the shot's mass (:mod:`peenflow.fe.shots`).
"""

from __future__ import annotations

import numpy as np

from peenflow.fe.mesh import BoxMesh

FIX_X, FIX_Y, FIX_Z = 1, 2, 4

_LATERAL = ("symmetric", "free")
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
    if bottom == "fixed":
        bc[-1, :, :] |= FIX_X | FIX_Y | FIX_Z
    return bc.ravel()
